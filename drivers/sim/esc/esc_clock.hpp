// The local clock of a simulated ESC: a 64-bit nanosecond counter driven by the slave's crystal
// (rate 1 + drift) and adjusted by the DC time control loop. The loop changes the clock in two ways,
// as the ESC's speed counter does: a speed correction (the clock runs faster or slower by a
// fraction, compensating the crystal's drift) and a phase correction (a bounded number of
// nanoseconds added or removed at a bounded rate, compensating a time difference).
//
//   local(t) = local(t0) + (t - t0) * rate * (1 + speed) + phase(t)
//   phase(t) = sign(B) * min(|B|, |rho| * (t - t0))     B: remaining phase budget, rho: its rate
//
// Segment time t is true time (the simulator's clock); local time is what the ESC counts. The
// clock is piecewise linear between loop updates, so it can also be inverted exactly: the segment
// time at which the local time reaches a value (SYNC0 events are scheduled in local terms).
#pragma once

#include <cstdint>
#include <limits>

#include "hal/time/clock.hpp"

namespace rescue::drivers {

class EscLocalClock {
 public:
  // Starts the clock at segment time `t` with local time `local` and a crystal deviation in ppm.
  void reset(hal::Nanoseconds t, std::uint64_t local, double drift_ppm) noexcept;

  // Local time at segment time `t` (t not before the last advance; earlier t is clamped to it).
  std::uint64_t local_at(hal::Nanoseconds t) const noexcept;
  // What time_of_local answers for a local time the clock cannot reach.
  static constexpr hal::Nanoseconds kNever = std::numeric_limits<hal::Nanoseconds>::max();

  // The earliest segment time at which local time has reached `local` (the last advance if it
  // already has; kNever if it never can).
  hal::Nanoseconds time_of_local(std::uint64_t local) const noexcept;

  // The segment time the clock was last advanced to: local_at(t) answers only for t from here on.
  hal::Nanoseconds advanced_to() const noexcept { return base_t_; }
  // Moves the clock's reference point to `t` (consuming phase budget on the way).
  void advance(hal::Nanoseconds t) noexcept;
  // The crystal's deviation changes at `t` (a temperature step): the clock runs at the new rate from `t` on.
  void change_crystal_drift(hal::Nanoseconds t, double drift_ppm) noexcept {
    advance(t);
    crystal_rate_ = 1.0 + drift_ppm * 1e-6;
    memo_valid_ = false;
  }

  // Loop outputs, applied from the last advance on.
  void set_speed_correction(double speed) noexcept {
    speed_ = speed;
    memo_valid_ = false;
  }
  void set_phase_correction(double budget_ns, double rate) noexcept;
  double speed_correction() const noexcept { return speed_; }
  double phase_budget() const noexcept { return phase_budget_; }

 private:
  // Local nanoseconds (with fraction) gained between the reference point and t0 + dt.
  double gained(double dt) const noexcept;
  // base_fraction_ + gained(t - base_t_), for t after the reference point (memo_ below).
  double total_at(hal::Nanoseconds t) const noexcept;

  hal::Nanoseconds base_t_{0};
  std::uint64_t base_local_{0};
  double base_fraction_{0.0};  // [0, 1)
  double crystal_rate_{1.0};
  double speed_{0.0};
  double phase_budget_{0.0};   // local ns still to add (negative: to remove)
  double phase_rate_{0.0};     // local ns per segment ns, same sign as the budget
  // The last total_at(): valid until the reference point or a rate changes.
  mutable bool memo_valid_{false};
  mutable hal::Nanoseconds memo_t_{0};
  mutable double memo_total_{0.0};
};

}  // namespace rescue::drivers
