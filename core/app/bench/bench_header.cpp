#include "core/app/bench/bench_header.hpp"

#include <sys/utsname.h>
#include <unistd.h>

#include <array>
#include <cstring>

namespace rescue::app {
namespace {

// "model name : X" from /proc/cpuinfo, or "unknown".
void cpu_model(std::array<char, 128>& model) noexcept {
  std::strcpy(model.data(), "unknown");  // NOLINT(clang-analyzer-security.insecureAPI.strcpy): fits
  std::FILE* cpuinfo = std::fopen("/proc/cpuinfo", "r");
  if (cpuinfo == nullptr) return;
  std::array<char, 256> line{};
  while (std::fgets(line.data(), static_cast<int>(line.size()), cpuinfo) != nullptr) {
    if (std::strncmp(line.data(), "model name", 10) != 0) continue;
    const char* colon = std::strchr(line.data(), ':');
    if (colon == nullptr) break;
    const char* value = colon + 1;
    while (*value == ' ') ++value;
    std::size_t n = std::strcspn(value, "\n");
    if (n >= model.size()) n = model.size() - 1;
    std::memcpy(model.data(), value, n);
    model[n] = '\0';
    break;
  }
  (void)std::fclose(cpuinfo);
}

}  // namespace

void print_bench_header(std::FILE* out, const char* name) noexcept {
  std::array<char, 128> model{};
  cpu_model(model);
  utsname system{};
  const bool have_uname = ::uname(&system) == 0;
  (void)std::fprintf(out, "bench: %s\n", name);
  (void)std::fprintf(out, "cpu: %s (%ld online)\n", model.data(), ::sysconf(_SC_NPROCESSORS_ONLN));
  (void)std::fprintf(out, "kernel: %s %s %s\n", have_uname ? system.sysname : "?", have_uname ? system.release : "?",
                     have_uname ? system.version : "?");
  (void)std::fprintf(out, "privileges: uid %u%s\n", static_cast<unsigned>(::geteuid()),
                     ::geteuid() == 0 ? " (root)" : " (unprivileged)");
}

bool kernel_is_preempt_rt() noexcept {
  utsname system{};
  if (::uname(&system) == 0 && std::strstr(system.version, "PREEMPT_RT") != nullptr) return true;
  std::FILE* f = std::fopen("/sys/kernel/realtime", "r");
  if (f == nullptr) return false;
  const int c = std::fgetc(f);
  (void)std::fclose(f);
  return c == '1';
}

}  // namespace rescue::app
