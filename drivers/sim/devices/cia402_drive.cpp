#include "drivers/sim/devices/cia402_drive.hpp"
#include "drivers/joint/joint_units.hpp"

#include <algorithm>
#include <cstdlib>

namespace rescue::drivers {
namespace {

using cia402::Command;
using cia402::State;

// Difference a - b of two wrapping 32-bit counter values.
std::int32_t counts_delta(std::int32_t a, std::int32_t b) noexcept {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b));
}

bool supported(std::int8_t mode) noexcept {
  return mode == static_cast<std::int8_t>(ControlMode::cyclic_position) ||
         mode == static_cast<std::int8_t>(ControlMode::cyclic_velocity) ||
         mode == static_cast<std::int8_t>(ControlMode::cyclic_torque) || mode == 0;
}

double rad(std::int64_t counts) noexcept { return static_cast<double>(counts) / drivers::kCountsPerRad; }

}  // namespace

Cia402Drive::Cia402Drive(const MotorLimits& limits, double initial_position_rad) noexcept
    : motor_(limits, initial_position_rad), target_position_rad_(initial_position_rad) {}

void Cia402Drive::power_up() noexcept { (void)machine_.apply(Command::self_test_done); }

void Cia402Drive::apply_outputs(const JointOutputs& outputs, bool valid, const DriveSettings& settings,
                                hal::Nanoseconds now) noexcept {
  const State before = machine_.state();
  machine_.set_fault_reset_allowed(!fault_cause_persists_);
  (void)machine_.apply_controlword(valid ? outputs.controlword : cia402::cw::kDisableVoltage);
  const State after = machine_.state();
  if (before == State::fault && after == State::switch_on_disabled) {
    error_code_ = drive_error::kNone;
    following_error_ = false;
    following_error_for_ = 0;
  }
  if (!valid) {
    last_outputs_at_ = -1;
    feed_forward_rad_s_ = 0.0;
    return;
  }
  if (supported(outputs.mode_of_operation)) mode_ = static_cast<ControlMode>(outputs.mode_of_operation);

  // The target relative to where the joint is, so a wrapping counter (tracks) works too.
  double target = motor_.position_rad() + rad(counts_delta(outputs.target_position, motor_.position_counts()));
  const MotorLimits& limits = motor_.limits();
  const double unclamped = target;
  if (!limits.continuous) target = std::max(rad(settings.position_min_counts), std::min(rad(settings.position_max_counts), target));
  // CSP targets outside the software position limits (0x607D) are clamped: internal limit active.
  target_clamped_ = mode_ == ControlMode::cyclic_position && target != unclamped;
  feed_forward_rad_s_ = 0.0;
  if (last_outputs_at_ >= 0 && now > last_outputs_at_ && before == State::operation_enabled) {
    // CSP interpolation: the master's targets move at this speed between cycles.
    const double dt = static_cast<double>(now - last_outputs_at_) * 1e-9;
    feed_forward_rad_s_ = rad(counts_delta(outputs.target_position, outputs_.target_position)) / dt;
  }
  if (after == State::operation_enabled && before != State::operation_enabled) following_error_for_ = 0;
  target_position_rad_ = target;
  outputs_ = outputs;
  last_outputs_at_ = now;
}

MotorCommand Cia402Drive::motor_command(const DriveSettings& settings) noexcept {
  const MotorLimits& limits = motor_.limits();
  // The limits in SI units change only when the settings do: converted once, not every step.
  if (!limits_converted_ || settings.max_torque_per_mille != converted_torque_per_mille_ ||
      settings.max_velocity_counts_s != converted_velocity_counts_s_) {
    converted_torque_per_mille_ = settings.max_torque_per_mille;
    converted_velocity_counts_s_ = settings.max_velocity_counts_s;
    torque_limit_nm_ = limits.rated_torque_nm * settings.max_torque_per_mille / 1000.0;
    velocity_limit_rad_s_ = rad(settings.max_velocity_counts_s);
    limits_converted_ = true;
  }
  MotorCommand c;
  c.torque_limit_nm = torque_limit_nm_;
  c.velocity_limit_rad_s = velocity_limit_rad_s_;
  switch (machine_.state()) {
    case State::operation_enabled:
      switch (mode_) {
        case ControlMode::cyclic_position:
          c.drive = MotorDrive::position;
          c.position_rad = target_position_rad_;
          c.velocity_rad_s = feed_forward_rad_s_;
          break;
        case ControlMode::cyclic_velocity:
          c.drive = MotorDrive::velocity;
          c.velocity_rad_s = rad(outputs_.target_velocity);
          break;
        case ControlMode::cyclic_torque:
          c.drive = MotorDrive::torque;
          c.torque_nm = limits.rated_torque_nm * outputs_.target_torque / 1000.0;
          break;
        case ControlMode::none:
          c.drive = MotorDrive::velocity;  // no mode: hold still under power
          break;
      }
      break;
    case State::quick_stop_active:
    case State::fault_reaction_active: c.drive = MotorDrive::braking; break;
    default: c.drive = MotorDrive::unpowered; break;
  }
  return c;
}

std::int32_t Cia402Drive::following_error_counts() const noexcept {
  return static_cast<std::int32_t>((target_position_rad_ - motor_.position_rad()) * drivers::kCountsPerRad);
}

void Cia402Drive::advance(hal::Nanoseconds dt, const DriveSettings& settings) noexcept {
  if (dt <= 0) return;
  motor_.step(motor_command(settings), dt);
  const State s = machine_.state();
  if ((s == State::quick_stop_active || s == State::fault_reaction_active) && motor_.standstill()) {
    (void)machine_.apply(Command::stopped);
  }
  following_error_ = false;
  if (s == State::operation_enabled && mode_ == ControlMode::cyclic_position) {
    const auto error = static_cast<std::uint32_t>(std::abs(following_error_counts()));
    if (error > settings.following_error_window_counts) {
      following_error_ = true;
      following_error_for_ += dt;
      if (following_error_for_ > static_cast<hal::Nanoseconds>(settings.following_error_timeout_ms) * hal::kNsPerMs) {
        raise(drive_error::kFollowingError);
      }
    } else {
      following_error_for_ = 0;
    }
  }
}

JointInputs Cia402Drive::inputs() const noexcept {
  namespace sw = cia402::sw;
  const State s = machine_.state();
  std::uint16_t status = cia402::statusword_bits(s);
  if (s == State::operation_enabled && mode_ != ControlMode::none) status |= sw::kFollowsCommand;
  if (following_error_) status |= sw::kFollowingError;
  if (motor_.limited() || target_clamped_) status |= sw::kInternalLimitActive;
  bool reached = false;
  if (s == State::operation_enabled) {
    switch (mode_) {
      case ControlMode::cyclic_position:
        reached = static_cast<std::uint32_t>(std::abs(following_error_counts())) < kPositionWindowCounts && motor_.standstill();
        break;
      case ControlMode::cyclic_velocity:
        reached = std::abs(counts_delta(motor_.velocity_counts_s(), outputs_.target_velocity)) <
                  static_cast<std::int32_t>(kPositionWindowCounts);
        break;
      case ControlMode::cyclic_torque: reached = std::abs(motor_.torque_per_mille() - outputs_.target_torque) < 10; break;
      case ControlMode::none: reached = motor_.standstill(); break;
    }
  } else if (s == State::quick_stop_active) {
    reached = motor_.standstill();
  }
  if (reached) status |= sw::kTargetReached;

  JointInputs in;
  in.statusword = status;
  in.mode_display = static_cast<std::int8_t>(mode_);
  in.position_actual = motor_.position_counts();
  in.velocity_actual = motor_.velocity_counts_s();
  in.torque_actual = motor_.torque_per_mille();
  in.error_code = error_code_;
  return in;
}

void Cia402Drive::raise(std::uint16_t error_code) noexcept {
  const State s = machine_.state();
  if (s == State::fault || s == State::fault_reaction_active) return;  // the first fault is kept
  error_code_ = error_code;
  (void)machine_.apply(Command::fault_detected);
}

void Cia402Drive::inject_fault(std::uint16_t error_code, bool persistent) noexcept {
  if (persistent) fault_cause_persists_ = true;
  raise(error_code);
}

void Cia402Drive::clear_fault_cause() noexcept { fault_cause_persists_ = false; }

}  // namespace rescue::drivers
