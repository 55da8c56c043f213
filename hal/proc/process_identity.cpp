#include "hal/proc/process_identity.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace rescue::hal {
namespace {

struct StatLine {
  char state{'?'};
  std::uint64_t start_time{0};
};

// Parses "/proc/PID/stat": "pid (comm) state f4 ... f22 ...". comm may hold spaces and ')', so the
// fields are counted after the last ')'.
Result<StatLine> read_stat(pid_t pid) noexcept {
  char path[64];
  (void)std::snprintf(path, sizeof path, "/proc/%d/stat", static_cast<int>(pid));
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT || errno == ESRCH) return make_error(Errc::not_found, "no such process");
    return make_error(Errc::io_error, "open /proc/PID/stat", static_cast<std::uint32_t>(errno));
  }
  char line[1024];
  const ssize_t n = ::read(fd, line, sizeof line - 1);
  const int err = errno;
  (void)::close(fd);
  if (n < 0) {
    if (err == ESRCH) return make_error(Errc::not_found, "no such process");
    return make_error(Errc::io_error, "read /proc/PID/stat", static_cast<std::uint32_t>(err));
  }
  line[n] = '\0';
  const char* close_paren = std::strrchr(line, ')');
  if (close_paren == nullptr || close_paren[1] != ' ') return make_error(Errc::malformed, "/proc/PID/stat line");
  StatLine out;
  out.state = close_paren[2];
  // Field 3 is the state; field 22 is starttime: 19 fields further on.
  const char* p = close_paren + 2;
  for (int field = 3; field < 22; ++field) {
    p = std::strchr(p, ' ');
    if (p == nullptr) return make_error(Errc::malformed, "/proc/PID/stat line");
    ++p;
  }
  char* end = nullptr;
  out.start_time = std::strtoull(p, &end, 10);
  if (end == p) return make_error(Errc::malformed, "/proc/PID/stat start time");
  return out;
}

}  // namespace

Result<std::uint64_t> process_start_time(pid_t pid) noexcept {
  const Result<StatLine> stat = read_stat(pid);
  if (!stat.ok()) return stat.error();
  return stat.value().start_time;
}

Result<ProcessIdentity> own_process_identity() noexcept {
  const pid_t pid = ::getpid();
  const Result<std::uint64_t> start = process_start_time(pid);
  if (!start.ok()) return start.error();
  return ProcessIdentity{static_cast<std::int32_t>(pid), start.value()};
}

bool process_alive(const ProcessIdentity& who) noexcept {
  if (who.pid <= 0) return false;
  const Result<StatLine> stat = read_stat(static_cast<pid_t>(who.pid));
  if (!stat.ok()) return false;
  if (stat.value().state == 'Z' || stat.value().state == 'X') return false;
  return stat.value().start_time == who.start_time;
}

std::int32_t own_thread_id() noexcept { return static_cast<std::int32_t>(::gettid()); }

}  // namespace rescue::hal
