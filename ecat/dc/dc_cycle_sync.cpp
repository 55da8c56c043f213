#include "ecat/dc/dc_cycle_sync.hpp"

namespace rescue::ecat {
namespace {

// x mod m in [0, m) for a signed x.
hal::Nanoseconds positive_mod(hal::Nanoseconds x, hal::Nanoseconds m) noexcept {
  const hal::Nanoseconds r = x % m;
  return r < 0 ? r + m : r;
}

}  // namespace

hal::Nanoseconds DcCycleSync::phase_error(std::uint64_t reference_time) const noexcept {
  // Difference first (modulo 2^64), then to signed: correct across any wrap of the system time.
  const auto since_start = static_cast<hal::Nanoseconds>(reference_time - sync0_start_);
  hal::Nanoseconds e = positive_mod(since_start - target_, cycle_);
  if (e >= cycle_ / 2) e -= cycle_;
  return e;
}

hal::Nanoseconds DcCycleSync::update(std::uint64_t reference_time) noexcept {
  const hal::Nanoseconds e = phase_error(reference_time);
  last_error_ = e;
  integral_ += static_cast<double>(e);
  double correction = -(kKp * static_cast<double>(e) + kKi * integral_);
  const double limit = static_cast<double>(cycle_) / 10.0;
  if (correction > limit) correction = limit;
  if (correction < -limit) correction = -limit;
  return static_cast<hal::Nanoseconds>(correction);
}

hal::Nanoseconds DcCycleSync::first_wakeup(hal::Nanoseconds now, hal::Nanoseconds master_time,
                                           std::uint64_t reference_time) const noexcept {
  // System time expected at `now`, and how far it is past the target phase.
  const std::uint64_t system_now = reference_time + static_cast<std::uint64_t>(now - master_time);
  const hal::Nanoseconds past_target = positive_mod(static_cast<hal::Nanoseconds>(system_now - sync0_start_) - target_, cycle_);
  return now + (cycle_ - past_target);
}

}  // namespace rescue::ecat
