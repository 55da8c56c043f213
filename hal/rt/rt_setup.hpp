// Real-time process set-up: lock memory, prefault the stack, SCHED_FIFO priority, CPU affinity.
// Each step returns a Status that says plainly why the OS refused (no privilege, CPU not present,
// limit too low). apply_rt_config() runs them all and never stops at a refusal: the program keeps
// going in a degraded mode and prints the report, one line per item, so nobody mistakes a laptop
// run for a real-time one.
//
//   rt: memory lock (mlockall current+future): applied
//   rt: CPU affinity 3: refused (out of range: CPU not present (CPU, CPUs present) = 3, 2)
//   rt: SCHED_FIFO priority 80: refused (permission denied: needs CAP_SYS_NICE or RLIMIT_RTPRIO ...)
//   rt: stack prefault 512 KiB: applied
//   rt: DEGRADED: 2 of 4 real-time settings refused; timing figures are not real-time
#pragma once

#include <sched.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "core/base/result.hpp"

namespace rescue::hal {

// Locks every current and future page in RAM (mlockall MCL_CURRENT | MCL_FUTURE): no page fault
// from swapping or lazy allocation once the process runs. Refused in ASan/TSan builds, whose shadow
// memory is terabytes of reserved address space.
Status lock_memory() noexcept;

// Touches `bytes` of the calling thread's stack now, so later deep calls do not fault. Refuses a
// size that does not fit in what is left of the thread's stack.
Status prefault_stack(std::size_t bytes) noexcept;

// SCHED_FIFO at `priority` (1..99) for the calling thread.
Status set_fifo_priority(int priority) noexcept;

// Pins the calling thread to one CPU.
Status pin_to_cpu(int cpu) noexcept;

// The calling thread's scheduling policy, priority and CPUs, saved before it runs real-time work for
// a while (the bring-up) and given back with restore_scheduling before it forks or runs normal work.
struct SchedulingState {
  int policy{SCHED_OTHER};
  int priority{0};
  cpu_set_t cpus{};
};
Result<SchedulingState> save_scheduling() noexcept;
Status restore_scheduling(const SchedulingState& state) noexcept;

// Stack each real-time task thread prefaults at start-up (apply_rt_config). The static stack check
// (toolchain/rt_verify.py, docs/verification.md) reads this line: every task's deepest period path
// must fit in it.
inline constexpr std::size_t kTaskStackPrefaultBytes = std::size_t{256} * 1024;

struct RtConfig {
  bool lock_memory{true};
  std::size_t prefault_stack_bytes{std::size_t{512} * 1024};  // 0: skip
  int fifo_priority{0};                           // 0: keep the default scheduler; 1..99: SCHED_FIFO
  int cpu{-1};                                    // -1: no pinning
  // The calling thread's timer slack (prctl PR_SET_TIMERSLACK), as cyclictest sets it: 1 ns. The
  // kernel ignores the slack of SCHED_FIFO threads, but a thread whose FIFO priority was refused
  // would otherwise sleep up to 50 us past its release. 0: leave it.
  unsigned long timer_slack_ns{0};
  // Holds the CPUs' wake-up latency at this many microseconds for the rest of the process (a PM QoS
  // request: /dev/cpu_dma_latency kept open, as cyclictest does unless --laptop): idle CPUs stay in
  // shallow idle states, so a timer or a frame wakes the thread without leaving a deep one (on a VM
  // with haltpoll: no halt, no VM exit). Costs power (an idle CPU polls). -1: leave it.
  int cpu_wakeup_latency_us{-1};
};

// The PM QoS request of RtConfig::cpu_wakeup_latency_us: opens /dev/cpu_dma_latency once per
// process and writes the value (kept open, so the request lasts until the process ends; a later call
// writes the new value). permission_denied without root, not_found where the kernel lacks it.
Status hold_cpu_wakeup_latency(int microseconds) noexcept;

enum class RtOutcome : std::uint8_t { applied, skipped, refused };
const char* to_string(RtOutcome outcome) noexcept;

struct RtItemReport {
  const char* item{""};       // "memory lock (mlockall current+future)", "SCHED_FIFO priority", ...
  std::int64_t parameter{-1};  // priority, CPU or size; -1 when none
  const char* unit{""};        // of the parameter, e.g. " KiB"
  RtOutcome outcome{RtOutcome::skipped};
  Error error{};  // why, when refused
};

struct RtReport {
  static constexpr std::size_t kItems = 6;
  std::array<RtItemReport, kItems> items{};

  bool fully_applied() const noexcept;  // nothing refused
  std::size_t refused_count() const noexcept;
  // Writes "rt: <item> [parameter]: applied|skipped|refused (<reason>)" lines.
  void print(std::FILE* out) const noexcept;
  // The same line for one item into `buffer` (NUL-terminated, truncated to fit); returns its length.
  static std::size_t format_item(const RtItemReport& item, char* buffer, std::size_t size) noexcept;
};

// Applies every item of `config` to the process and the calling thread; never stops at a refusal.
RtReport apply_rt_config(const RtConfig& config) noexcept;

// Page faults so far (getrusage): the "no page fault after init" figure is the difference of two
// readings. `minor`: page mapped without I/O (first touch, copy-on-write); `major`: needed I/O.
struct PageFaults {
  std::uint64_t minor{0};
  std::uint64_t major{0};
};
PageFaults page_faults_of_process() noexcept;
PageFaults page_faults_of_thread() noexcept;

// Names the calling thread (prctl PR_SET_NAME, at most 15 characters kept): `ps -eLo comm`, `top -H`
// and /proc/PID/task/TID/comm show it. A process's main thread names the process too.
Status name_this_thread(const char* name) noexcept;

// What the kernel reports for the calling thread: its scheduling policy (sched_getscheduler),
// priority (sched_getparam) and the CPU it runs on now (sched_getcpu). -1 where the call failed.
struct ThreadSchedule {
  int policy{-1};    // SCHED_OTHER 0, SCHED_FIFO 1, SCHED_RR 2, SCHED_BATCH 3, SCHED_IDLE 5, SCHED_DEADLINE 6
  int priority{-1};  // 0 for the normal policies
  int cpu{-1};
};
ThreadSchedule thread_schedule() noexcept;
// "FIFO", "RR", "OTHER", "BATCH", "IDLE", "DEADLINE", or "?".
const char* policy_name(int policy) noexcept;

}  // namespace rescue::hal
