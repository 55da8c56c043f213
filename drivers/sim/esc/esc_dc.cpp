#include "drivers/sim/esc/esc_dc.hpp"

#include <algorithm>
#include <cmath>

#include "drivers/sim/devices/inline_math.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

namespace reg = ecat::reg;

constexpr std::uint16_t kSpeedCounterStartReset = 0x1000;
constexpr std::uint8_t kTimeDiffFilterDepthReset = 0x04;
constexpr std::uint8_t kSpeedCounterFilterDepthReset = 0x0C;
constexpr std::uint16_t kSpeedCounterStartMin = 0x0080;
constexpr double kMaxPhaseRate = 1e-3;  // the phase correction never exceeds 1000 ppm
constexpr double kMinIntervalNs = 1e3;
constexpr double kMaxIntervalNs = 1e8;
// Pulses further behind than this many cycles are skipped rather than replayed (a jump of the
// system time by the master's offset write).
constexpr std::uint64_t kMaxSync0CatchUp = 1000;

// Clock deviation the speed counter represents: corrections of +-1 ns applied every (S +- D + 2)
// ticks of 10 ns give a net fraction D / (5 ((S+2)^2 - D^2)).
double speed_of_counter_diff(double start, double diff) noexcept {
  const double s2 = (start + 2.0) * (start + 2.0);
  return diff / (5.0 * (s2 - diff * diff));
}

double max_speed(std::uint16_t start) noexcept {
  const double s = std::max<double>(start, kSpeedCounterStartMin);
  return speed_of_counter_diff(s, s - 127.0);
}

}  // namespace

void EscDc::reset(EscMemory& memory, const EscConfig& config, hal::Nanoseconds now) noexcept {
  clock_.reset(now, config.local_time_at_zero + static_cast<std::uint64_t>(now > 0 ? now : 0), config.drift_ppm);
  sync0_active_ = false;
  next_sync0_ = 0;
  start_time_written_ = 0;
  mean_difference_ = 0.0;
  have_previous_write_ = false;
  previous_write_local_ = 0;
  interval_estimate_ns_ = 1e6;
  if (!config.dc_supported) return;
  memory.set_u16(reg::kDcSpeedCounterStart, kSpeedCounterStartReset);
  memory.set_u8(reg::kDcTimeDiffFilterDepth, kTimeDiffFilterDepthReset);
  memory.set_u8(reg::kDcSpeedCounterFilterDepth, kSpeedCounterFilterDepthReset);
}

std::uint64_t EscDc::system_time_at(const EscMemory& memory, hal::Nanoseconds t) const noexcept {
  return clock_.local_at(t) + memory.u64(reg::kDcSystemTimeOffset);
}

void EscDc::on_frame_start(EscMemory& memory, hal::Nanoseconds t) noexcept {
  clock_.advance(t);
  memory.set_u64(reg::kDcSystemTime, system_time_at(memory, t));
}

void EscDc::latch_receive_times(EscMemory& memory, const std::array<hal::Nanoseconds, kMaxEscPorts>& arrival,
                                const std::array<bool, kMaxEscPorts>& arrived) noexcept {
  for (unsigned port = 0; port < kMaxEscPorts; ++port) {
    if (!arrived[port]) continue;
    const std::uint64_t local = clock_.local_at(arrival[port]);
    memory.set_u32(reg::dc_receive_time_port(port), static_cast<std::uint32_t>(local));
    if (port == 0) memory.set_u64(reg::kDcReceiveTimeEpu, local);
  }
}

void EscDc::on_system_time_write(EscMemory& memory, std::uint64_t received, unsigned bytes,
                                 hal::Nanoseconds t) noexcept {
  const std::uint64_t local_copy = memory.u64(reg::kDcSystemTime);  // latched at frame start
  const std::uint32_t delay = memory.u32(reg::kDcSystemTimeDelay);
  const std::uint64_t expected = received + delay;
  // A 32-bit write compares the low halves only.
  const double difference = bytes >= 8 ? static_cast<double>(static_cast<std::int64_t>(expected - local_copy))
                                       : static_cast<double>(static_cast<std::int32_t>(
                                             static_cast<std::uint32_t>(expected) - static_cast<std::uint32_t>(local_copy)));

  const unsigned filter_depth = memory.u8(reg::kDcTimeDiffFilterDepth) & 0x0FU;
  // x / 2^k and x * 2^-k are the same double (2^-k is exact): no division on the way.
  mean_difference_ += (difference - mean_difference_) * (1.0 / static_cast<double>(1U << filter_depth));
  const double shown = inline_math::fmin(std::fabs(mean_difference_), 2147483647.0);
  memory.set_u32(reg::kDcSystemTimeDifference,
                 static_cast<std::uint32_t>(inline_math::llround(shown)) | (mean_difference_ > 0.0 ? reg::kDcDiffLocalSmaller : 0U));

  const std::uint64_t local_now = clock_.local_at(t);
  const SpeedCounterTerms& terms = speed_counter_terms(memory);
  const double kp = terms.kp;
  const double ki = 1.0 / static_cast<double>(1U << (memory.u8(reg::kDcSpeedCounterFilterDepth) & 0x0FU));
  clock_.advance(t);
  if (have_previous_write_ && local_now > previous_write_local_) {
    const double interval = std::clamp(static_cast<double>(local_now - previous_write_local_), kMinIntervalNs, kMaxIntervalNs);
    const double limit = terms.max_speed;
    clock_.set_speed_correction(std::clamp(clock_.speed_correction() + ki * difference / interval, -limit, limit));
    interval_estimate_ns_ = interval;
  }
  const double budget = kp * difference;
  clock_.set_phase_correction(budget, inline_math::fmin(std::fabs(budget) / interval_estimate_ns_, kMaxPhaseRate));
  have_previous_write_ = true;
  previous_write_local_ = local_now;
  update_speed_counter_diff(memory);
}

const EscDc::SpeedCounterTerms& EscDc::speed_counter_terms(const EscMemory& memory) noexcept {
  const std::uint16_t written = memory.u16(reg::kDcSpeedCounterStart);
  if (!terms_valid_ || written != terms_.written) {
    const std::uint16_t start = std::max<std::uint16_t>(written, kSpeedCounterStartMin);
    const auto s = static_cast<double>(start);
    terms_.written = written;
    terms_.kp = std::clamp(256.0 / s, 1.0 / 256.0, 0.5);
    terms_.max_speed = max_speed(start);
    terms_.start_plus_2_squared = (s + 2.0) * (s + 2.0);
    terms_.limit = s - 127.0;
    terms_valid_ = true;
  }
  return terms_;
}

void EscDc::update_speed_counter_diff(EscMemory& memory) noexcept {
  const SpeedCounterTerms& terms = speed_counter_terms(memory);
  const double c = clock_.speed_correction();
  double diff = 0.0;
  if (c != 0.0) {
    // Inverse of speed_of_counter_diff: 5c D^2 + D - 5c (S+2)^2 = 0.
    const double a = 5.0 * c;
    const double s2 = terms.start_plus_2_squared;
    diff = (-1.0 + std::sqrt(1.0 + 4.0 * a * a * s2)) / (2.0 * a);
  }
  const double limit = terms.limit;
  memory.set_u16(reg::kDcSpeedCounterDiff,
                 static_cast<std::uint16_t>(static_cast<std::int16_t>(inline_math::llround(std::clamp(diff, -limit, limit)))));
}

void EscDc::on_speed_counter_start_write(EscMemory& memory) noexcept {
  clock_.set_speed_correction(0.0);
  clock_.set_phase_correction(0.0, 0.0);
  mean_difference_ = 0.0;
  have_previous_write_ = false;
  memory.set_u32(reg::kDcSystemTimeDifference, 0);
  memory.set_u16(reg::kDcSpeedCounterDiff, 0);
}

void EscDc::on_start_time_write(EscMemory& memory) noexcept {
  start_time_written_ = memory.u64(reg::kDcStartTime);
  if (sync0_active_) memory.set_u64(reg::kDcStartTime, next_sync0_);  // reads show the next pulse
}

void EscDc::on_activation_write(EscMemory& memory, hal::Nanoseconds t) noexcept {
  const std::uint8_t activation = memory.u8(reg::kDcActivation);
  const bool want = (activation & reg::kDcActivateCyclic) != 0 && (activation & reg::kDcActivateSync0) != 0;
  if (!want) {
    sync0_active_ = false;
    memory.set_u8(reg::kDcActivationStatus, 0);
    return;
  }
  if (sync0_active_) return;
  const std::uint64_t now_system = system_time_at(memory, t);
  std::uint64_t first = start_time_written_;
  if (static_cast<std::int64_t>(first - now_system) <= 0) {
    // In the past: the ESC compares the low 32 bits and waits until they come round again.
    std::uint32_t wait = static_cast<std::uint32_t>(first) - static_cast<std::uint32_t>(now_system);
    first = now_system + (wait == 0 ? (std::uint64_t{1} << 32) : wait);
  }
  sync0_active_ = true;
  next_sync0_ = first;
  memory.set_u64(reg::kDcStartTime, next_sync0_);
  memory.set_u8(reg::kDcActivationStatus, 0x01);  // first SYNC0 pulse pending
}

bool EscDc::sync0_due(const EscMemory& memory, hal::Nanoseconds t, hal::Nanoseconds& when) const noexcept {
  if (!sync0_active_) return false;
  const std::uint64_t local = next_sync0_ - memory.u64(reg::kDcSystemTimeOffset);
  const std::uint64_t now_local = clock_.local_at(t);
  if (static_cast<std::int64_t>(local - now_local) > 0) return false;
  // Due by the ESC's wrapping comparison; a pulse time numerically ahead (it wrapped round) is
  // due now, not when the 64-bit counter reaches it.
  when = local > now_local ? t : clock_.time_of_local(local);
  return true;
}

std::uint64_t EscDc::fire_sync0(EscMemory& memory) noexcept {
  const std::uint64_t pulse = next_sync0_;
  const std::uint32_t cycle = memory.u32(reg::kDcSync0CycleTime);
  memory.set_u8(reg::kDcSync0Status, static_cast<std::uint8_t>(memory.u8(reg::kDcSync0Status) | 0x01U));
  memory.set_u8(reg::kDcActivationStatus, 0);
  if (cycle == 0) {
    sync0_active_ = false;  // single shot
    return pulse;
  }
  next_sync0_ += cycle;
  // After a jump of the system time, skip pulses instead of replaying thousands of them.
  const std::uint64_t now_system = memory.u64(reg::kDcSystemTime);
  if (static_cast<std::int64_t>(now_system - next_sync0_) > static_cast<std::int64_t>(kMaxSync0CatchUp * cycle)) {
    next_sync0_ += ((now_system - next_sync0_) / cycle + 1) * cycle;
  }
  memory.set_u64(reg::kDcStartTime, next_sync0_);
  return pulse;
}

}  // namespace rescue::drivers
