#include "drivers/sim/esc/esc_clock.hpp"

#include <cmath>

#include "drivers/sim/devices/inline_math.hpp"

namespace rescue::drivers {

void EscLocalClock::reset(hal::Nanoseconds t, std::uint64_t local, double drift_ppm) noexcept {
  base_t_ = t;
  base_local_ = local;
  base_fraction_ = 0.0;
  crystal_rate_ = 1.0 + drift_ppm * 1e-6;
  speed_ = 0.0;
  phase_budget_ = 0.0;
  phase_rate_ = 0.0;
  memo_valid_ = false;
}

void EscLocalClock::set_phase_correction(double budget_ns, double rate) noexcept {
  phase_budget_ = budget_ns;
  phase_rate_ = budget_ns == 0.0 ? 0.0 : std::copysign(std::fabs(rate), budget_ns);
  memo_valid_ = false;
}

double EscLocalClock::gained(double dt) const noexcept {
  const double linear = dt * crystal_rate_ * (1.0 + speed_);
  if (phase_rate_ == 0.0) return linear;
  const double phase = inline_math::fmin(std::fabs(phase_budget_), std::fabs(phase_rate_) * dt);
  return linear + std::copysign(phase, phase_budget_);
}

double EscLocalClock::total_at(hal::Nanoseconds t) const noexcept {
  // The ESC asks for the same instant twice in a row (is SYNC0 due at t? then advance to t):
  // remembered until the clock changes, computed once.
  if (memo_valid_ && memo_t_ == t) return memo_total_;
  memo_total_ = base_fraction_ + gained(static_cast<double>(t - base_t_));
  memo_t_ = t;
  memo_valid_ = true;
  return memo_total_;
}

std::uint64_t EscLocalClock::local_at(hal::Nanoseconds t) const noexcept {
  // At (or before) the reference point nothing was gained: the formula below gives base_local_
  // exactly (the fraction is in [0, 1)), so skip it. Most reads are of the time just advanced to.
  if (t <= base_t_) return base_local_;
  const double total = total_at(t);
  // The clock never runs backwards (|phase rate| stays far below the crystal rate).
  const double whole = inline_math::floor(total);
  return base_local_ + static_cast<std::uint64_t>(whole > 0.0 ? whole : 0.0);
}

hal::Nanoseconds EscLocalClock::time_of_local(std::uint64_t local) const noexcept {
  if (local <= base_local_) return base_t_;
  const double need = static_cast<double>(local - base_local_) - base_fraction_;
  const double linear_rate = crystal_rate_ * (1.0 + speed_);
  double dt = 0.0;
  if (phase_rate_ == 0.0) {
    dt = need / linear_rate;
  } else {
    const double phase_duration = std::fabs(phase_budget_ / phase_rate_);
    const double during_phase = phase_duration * (linear_rate + phase_rate_);
    dt = need <= during_phase ? need / (linear_rate + phase_rate_)
                              : phase_duration + (need - during_phase) / linear_rate;
  }
  // A local time the clock cannot reach within the segment's time range (a start time written
  // decades ahead, or one that wrapped round): never, rather than an unrepresentable conversion.
  const double reachable = static_cast<double>(kNever - base_t_) / 2.0;
  if (!(dt < reachable)) return kNever;
  hal::Nanoseconds t = base_t_ + static_cast<hal::Nanoseconds>(inline_math::ceil(dt));
  // Rounding of the double arithmetic: step to the first nanosecond that really reaches `local`.
  while (t > base_t_ && local_at(t - 1) >= local) --t;
  while (local_at(t) < local) ++t;
  return t;
}

void EscLocalClock::advance(hal::Nanoseconds t) noexcept {
  if (t <= base_t_) return;
  const auto dt = static_cast<double>(t - base_t_);
  const double total = total_at(t);
  memo_valid_ = false;  // the reference point moves
  if (phase_rate_ != 0.0) {
    const double used = inline_math::fmin(std::fabs(phase_budget_), std::fabs(phase_rate_) * dt);
    phase_budget_ -= std::copysign(used, phase_budget_);
    if (std::fabs(phase_budget_) < 1e-9) {
      phase_budget_ = 0.0;
      phase_rate_ = 0.0;
    }
  }
  const double whole = inline_math::floor(total);
  base_local_ += static_cast<std::uint64_t>(whole > 0.0 ? whole : 0.0);
  base_fraction_ = total - whole;
  base_t_ = t;
}

}  // namespace rescue::drivers
