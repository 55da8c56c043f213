// A bench that steps real-time code flat out in virtual time on a SCHED_FIFO thread would run its CPU
// at 100 %: the kernel's real-time throttling (/proc/sys/kernel/sched_rt_runtime_us, 950 000 of every
// 1 000 000 us by default) then stops the thread for up to 50 ms, in the middle of whatever period it
// was timing. Measured on this 2-vCPU VM, quiet: `bench wcet --scenario worst` gave the EtherCAT
// handler an 18.4 ms "period" with throttling on and 0.51 ms with it off (sched_rt_runtime_us -1).
// RtDutyRest rests the thread between periods (never inside one): kRestNs after every kBusyNs of wall
// time, so the thread's real-time share stays below the throttle's (docs/timing.md "bench wcet").
#pragma once

#include <cstdint>

namespace rescue::app {

class RtDutyRest {
 public:
  static constexpr std::int64_t kBusyNs = 100'000'000;  // 100 ms busy ...
  static constexpr std::int64_t kRestNs = 10'000'000;   // ... then 10 ms asleep: 91 % < 95 %

  RtDutyRest() noexcept;
  // Between two measured periods: sleeps kRestNs once kBusyNs have passed since the last rest.
  void between_periods() noexcept;
  std::uint64_t rests() const noexcept { return rests_; }
  // The kernel's real-time share (sched_rt_runtime_us of sched_rt_period_us) as text, "n/a" when unreadable.
  static void describe_throttle(char* out, std::size_t size) noexcept;

 private:
  std::int64_t busy_since_ns_;
  std::uint64_t rests_{0};
};

}  // namespace rescue::app
