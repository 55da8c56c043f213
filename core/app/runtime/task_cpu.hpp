// The CPU time of every task, per second of wall time, in an idle and in a moving phase of a run
// (`run`'s summary: docs/timing.md "The whole firmware's CPU"), so the motion PC's budget is visible.
// Read from the kernel's per-thread accounting, /proc/PID/task/TID/schedstat (nanoseconds on the
// CPU) and .../comm (the task's thread name, hal::name_this_thread), of this process and of the task
// processes, by the logger or the supervisor (a normal thread), never inside a real-time period.
// Fixed capacity, no heap: up to kMaxThreads threads, summed by name (a restarted task process
// counts under the same name).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "core/base/span.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

constexpr std::size_t kTaskCpuMaxThreads = 32;
constexpr std::size_t kTaskCpuNameSize = 16;  // TASK_COMM_LEN
// The meter reads the threads at most this often (and at each phase change): ~20 small /proc reads.
constexpr hal::Nanoseconds kTaskCpuSampleEvery = 100 * hal::kNsPerMs;

struct TaskCpuSample {
  hal::Nanoseconds at{0};  // wall (CLOCK_MONOTONIC) when it was read
  std::size_t count{0};
  std::array<std::array<char, kTaskCpuNameSize>, kTaskCpuMaxThreads> names{};
  std::array<std::uint64_t, kTaskCpuMaxThreads> cpu_ns{};  // summed over the threads of that name
  std::size_t unread{0};  // threads whose files could not be read (ended meanwhile) or beyond capacity

  // Adds `ns` under `name` (a new row when the name is new and there is room).
  void add(const char* name, std::uint64_t ns) noexcept;
  // The row of `name`, or kTaskCpuMaxThreads.
  std::size_t find(const char* name) const noexcept;
};

// Reads every thread of the processes `pids` (duplicates read once), at `now`.
TaskCpuSample read_task_cpu(Span<const int> pids, hal::Nanoseconds now) noexcept;

// CPU ms per second of wall time of each name between two samples (names of `to`; a thread that
// is missing in `from` counts from 0). Prints `cpu_ms_per_s_<phase>_<name>: X` lines (names with
// '-' as '_'), then `..._total` and `wall_s_<phase>`. Nothing when the phase lasted 0.
void print_task_cpu(std::FILE* out, const char* phase, const TaskCpuSample& from, const TaskCpuSample& to) noexcept;

// The run's two phases, sampled by the logger's (threads) or supervisor's (processes) loop:
// idle = init complete to the first period an RC task's references drive joints (the Motion owner's),
// or to the end without one; moving = from there to the handler's last period (its stop excluded).
class TaskCpuMeter {
 public:
  // One pass of the loop: `moving` once the motion started, `done` once the handler ended.
  void observe(Span<const int> pids, hal::Clock& clock, bool moving, bool done) noexcept;
  void print(std::FILE* out) const noexcept;

 private:
  TaskCpuSample start_{};
  TaskCpuSample motion_{};
  TaskCpuSample last_{};
  bool started_{false};
  bool moved_{false};
  bool finished_{false};
};

// The run's meter (static storage), observed by the logger's or the supervisor's loop.
TaskCpuMeter& run_task_cpu() noexcept;

}  // namespace rescue::app
