#include "core/app/bench/rt_duty_rest.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <ctime>

namespace rescue::app {
namespace {

std::int64_t monotonic_ns() noexcept {
  timespec now{};
  (void)::clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

// One integer from a /proc file; -2 when unreadable (-1 is the kernel's "no throttling").
long read_proc_long(const char* path) noexcept {
  std::FILE* file = std::fopen(path, "r");
  if (file == nullptr) return -2;
  char line[32] = "";
  const bool read = std::fgets(line, sizeof line, file) != nullptr;
  (void)std::fclose(file);
  if (!read) return -2;
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(line, &end, 10);
  return errno != 0 || end == line ? -2 : value;
}

}  // namespace

RtDutyRest::RtDutyRest() noexcept : busy_since_ns_(monotonic_ns()) {}

void RtDutyRest::between_periods() noexcept {
  const std::int64_t now = monotonic_ns();
  if (now - busy_since_ns_ < kBusyNs) return;
  const timespec rest{0, kRestNs};
  (void)::clock_nanosleep(CLOCK_MONOTONIC, 0, &rest, nullptr);  // an interrupted rest is only shorter
  ++rests_;
  busy_since_ns_ = monotonic_ns();
}

void RtDutyRest::describe_throttle(char* out, std::size_t size) noexcept {
  const long runtime = read_proc_long("/proc/sys/kernel/sched_rt_runtime_us");
  const long period = read_proc_long("/proc/sys/kernel/sched_rt_period_us");
  if (runtime == -2 || period == -2) {
    (void)std::snprintf(out, size, "n/a");
  } else if (runtime == -1) {
    (void)std::snprintf(out, size, "off (sched_rt_runtime_us -1)");
  } else {
    (void)std::snprintf(out, size, "%ld of every %ld us", runtime, period);
  }
}

}  // namespace rescue::app
