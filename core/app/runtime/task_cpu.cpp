#include "core/app/runtime/task_cpu.hpp"

#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cinttypes>
#include <cstdlib>
#include <cstring>

namespace rescue::app {
namespace {

// The first line of a small /proc file into `buffer` (zero-terminated, newline removed). open/read:
// no stdio buffer, so no heap (the meter runs after init, where the heap guard counts).
bool read_line(const char* path, char* buffer, std::size_t size) noexcept {
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const ssize_t got = ::read(fd, buffer, size - 1);
  (void)::close(fd);
  if (got <= 0) return false;
  buffer[got] = '\0';
  buffer[std::strcspn(buffer, "\n")] = '\0';
  return true;
}

void read_thread(int pid, const char* tid, TaskCpuSample& sample) noexcept {
  char path[96];
  char name[kTaskCpuNameSize + 8];
  char line[96];
  (void)std::snprintf(path, sizeof path, "/proc/%d/task/%.16s/comm", pid, tid);
  if (!read_line(path, name, sizeof name)) {
    ++sample.unread;
    return;
  }
  (void)std::snprintf(path, sizeof path, "/proc/%d/task/%.16s/schedstat", pid, tid);
  if (!read_line(path, line, sizeof line)) {
    ++sample.unread;
    return;
  }
  // schedstat: "<ns on the CPU> <ns waiting on a runqueue> <timeslices>".
  char* end = nullptr;
  const unsigned long long on_cpu = std::strtoull(line, &end, 10);
  if (end == line) {
    ++sample.unread;
    return;
  }
  name[kTaskCpuNameSize - 1] = '\0';
  sample.add(name, on_cpu);
}

// Every thread of `pid` (/proc/PID/task), listed with getdents64 (opendir would allocate).
void read_process(int pid, TaskCpuSample& sample) noexcept {
  char dir_path[48];
  (void)std::snprintf(dir_path, sizeof dir_path, "/proc/%d/task", pid);
  const int fd = ::open(dir_path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) {
    ++sample.unread;
    return;
  }
  alignas(8) std::array<char, 4096> entries{};
  for (;;) {
    const long got = ::syscall(SYS_getdents64, fd, entries.data(), entries.size());
    if (got <= 0) break;
    for (long at = 0; at < got;) {
      // struct linux_dirent64: u64 d_ino, s64 d_off, u16 d_reclen, u8 d_type, char d_name[].
      std::uint16_t length = 0;
      std::memcpy(&length, entries.data() + at + 16, sizeof length);
      const char* tid = entries.data() + at + 19;
      if (length == 0) break;
      if (tid[0] != '.') read_thread(pid, tid, sample);
      at += length;
    }
  }
  (void)::close(fd);
}

}  // namespace

std::size_t TaskCpuSample::find(const char* name) const noexcept {
  for (std::size_t i = 0; i < count; ++i) {
    if (std::strncmp(names[i].data(), name, kTaskCpuNameSize) == 0) return i;
  }
  return kTaskCpuMaxThreads;
}

void TaskCpuSample::add(const char* name, std::uint64_t ns) noexcept {
  std::size_t row = find(name);
  if (row == kTaskCpuMaxThreads) {
    if (count == kTaskCpuMaxThreads) {
      ++unread;
      return;
    }
    row = count++;
    (void)std::snprintf(names[row].data(), kTaskCpuNameSize, "%.15s", name);
    cpu_ns[row] = 0;
  }
  cpu_ns[row] += ns;
}

TaskCpuSample read_task_cpu(Span<const int> pids, hal::Nanoseconds now) noexcept {
  TaskCpuSample sample;
  sample.at = now;
  for (std::size_t i = 0; i < pids.size(); ++i) {
    if (pids[i] <= 0) continue;
    bool seen = false;
    for (std::size_t j = 0; j < i; ++j) seen = seen || pids[j] == pids[i];
    if (!seen) read_process(pids[i], sample);
  }
  return sample;
}

void print_task_cpu(std::FILE* out, const char* phase, const TaskCpuSample& from, const TaskCpuSample& to) noexcept {
  const hal::Nanoseconds wall = to.at - from.at;
  if (wall <= 0) return;
  const double seconds = static_cast<double>(wall) / 1e9;
  double total = 0.0;
  for (std::size_t i = 0; i < to.count; ++i) {
    const std::size_t before = from.find(to.names[i].data());
    const std::uint64_t base = before < from.count ? from.cpu_ns[before] : 0;
    const std::uint64_t used = to.cpu_ns[i] > base ? to.cpu_ns[i] - base : 0;
    const double ms_per_s = static_cast<double>(used) / 1e6 / seconds;
    total += ms_per_s;
    char key[kTaskCpuNameSize];
    std::size_t n = 0;
    for (; n + 1 < sizeof key && to.names[i][n] != '\0'; ++n) key[n] = to.names[i][n] == '-' ? '_' : to.names[i][n];
    key[n] = '\0';
    (void)std::fprintf(out, "cpu_ms_per_s_%s_%s: %.2f\n", phase, key, ms_per_s);
  }
  (void)std::fprintf(out, "cpu_ms_per_s_%s_total: %.2f\n", phase, total);
  (void)std::fprintf(out, "wall_s_%s: %.3f\n", phase, seconds);
}

void TaskCpuMeter::observe(Span<const int> pids, hal::Clock& clock, bool moving, bool done) noexcept {
  if (finished_) return;
  if (done) {  // the handler ended: its stop is not part of either phase; keep the last sample
    finished_ = true;
    return;
  }
  const hal::Nanoseconds at = clock.now();
  const bool phase_change = !started_ || (moving && !moved_);
  if (!phase_change && at - last_.at < kTaskCpuSampleEvery) return;
  const TaskCpuSample now = read_task_cpu(pids, at);
  if (!started_) {
    start_ = now;
    started_ = true;
  }
  if (moving && !moved_) {
    motion_ = now;
    moved_ = true;
  }
  last_ = now;
}

void TaskCpuMeter::print(std::FILE* out) const noexcept {
  if (!started_) return;
  print_task_cpu(out, "idle", start_, moved_ ? motion_ : last_);
  if (moved_) print_task_cpu(out, "moving", motion_, last_);
}

TaskCpuMeter& run_task_cpu() noexcept {
  static TaskCpuMeter meter;
  return meter;
}

}  // namespace rescue::app
