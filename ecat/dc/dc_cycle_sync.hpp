// Keeping the master's cycle in step with the network's time (the DC reference clock), so the
// Linux clock that wakes the master and the DC system time that fires SYNC0 do not drift apart
// (IgH's "sync reference to master" inverted, as SOEM's ec_sync() example does).
//
// Every cyclic frame reads the reference clock's system time (FRMW 0x0910) as the frame passes
// it. Its phase in the SYNC0 period, (t_ref - sync0_start) mod T, should stay at `target_phase`
// (half a period after SYNC0 by default: outputs then arrive half a period before the next SYNC0
// latches them). A PI controller on the phase error shifts the master's next wake-up:
//
//   e_k = wrap((t_ref,k - s0) mod T - target)          in [-T/2, T/2)
//   next wake-up = previous + T - (Kp e_k + Ki sum e)   (correction clamped to T/10)
//
// With Kp = 0.1 and Ki = 0.005 the loop's poles have radius sqrt(1 - Kp) ~ 0.95: a disturbance
// decays in about 20 cycles, and the integral absorbs a constant drift (100 ppm = 100 ns per 1 ms
// cycle) with no steady phase error.
#pragma once

#include <cstdint>

#include "hal/time/clock.hpp"

namespace rescue::ecat {

class DcCycleSync {
 public:
  DcCycleSync() = default;
  DcCycleSync(hal::Nanoseconds cycle, std::uint64_t sync0_start, hal::Nanoseconds target_phase) noexcept
      : cycle_(cycle), sync0_start_(sync0_start), target_(target_phase) {}

  // Phase error of a frame that passed the reference at system time `reference_time`.
  hal::Nanoseconds phase_error(std::uint64_t reference_time) const noexcept;

  // Feeds one cycle's reference time; returns the shift to add to the next nominal wake-up.
  hal::Nanoseconds update(std::uint64_t reference_time) noexcept;

  // First wake-up (master clock) after `now` that puts the frame at the target phase, given that
  // at master time `master_time` the reference read `reference_time`.
  hal::Nanoseconds first_wakeup(hal::Nanoseconds now, hal::Nanoseconds master_time, std::uint64_t reference_time) const noexcept;

  hal::Nanoseconds last_error() const noexcept { return last_error_; }
  hal::Nanoseconds cycle() const noexcept { return cycle_; }

  static constexpr double kKp = 0.1;
  static constexpr double kKi = 0.005;

 private:
  hal::Nanoseconds cycle_{hal::kNsPerMs};
  std::uint64_t sync0_start_{0};
  hal::Nanoseconds target_{hal::kNsPerMs / 2};
  double integral_{0.0};
  hal::Nanoseconds last_error_{0};
};

}  // namespace rescue::ecat
