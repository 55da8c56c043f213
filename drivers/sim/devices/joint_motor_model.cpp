#include "drivers/sim/devices/joint_motor_model.hpp"
#include "drivers/joint/joint_units.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "drivers/sim/devices/inline_math.hpp"

namespace rescue::drivers {
namespace {

// max(-limit, min(limit, v)). The usual case, inside the limits, is a branch the CPU predicts:
// min/max instructions would sit on the integration's dependency chain (docs/simulator.md, Speed).
// Same result bit for bit: inside the limits both forms return v.
double clamp(double v, double limit) noexcept {
  if (v < limit && -limit < v) return v;
  return std::max(-limit, std::min(limit, v));
}

constexpr double kStandstillRadS = 1e-4;
constexpr double kTwoTo32 = 4294967296.0;

std::uint64_t bits_of(double v) noexcept {
  std::uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

}  // namespace

JointMotorModel::JointMotorModel(const MotorLimits& limits, double initial_position_rad) noexcept
    : limits_(limits),
      acceleration_max_(limits.velocity_max_rad_s / kAccelerationTime),
      position_(initial_position_rad) {
  inertia_ = limits.torque_max_nm / acceleration_max_;
}

bool JointMotorModel::standstill() const noexcept { return std::fabs(velocity_) < kStandstillRadS; }

bool JointMotorModel::rests_under(const MotorCommand& c, hal::Nanoseconds h) const noexcept {
  return rest_.known && h <= rest_.h && c.drive == rest_.command.drive &&
         bits_of(c.position_rad) == bits_of(rest_.command.position_rad) &&
         bits_of(c.velocity_rad_s) == bits_of(rest_.command.velocity_rad_s) &&
         bits_of(c.torque_nm) == bits_of(rest_.command.torque_nm) &&
         bits_of(c.torque_limit_nm) == bits_of(rest_.command.torque_limit_nm) &&
         bits_of(c.velocity_limit_rad_s) == bits_of(rest_.command.velocity_limit_rad_s);
}

void JointMotorModel::step(const MotorCommand& command, hal::Nanoseconds dt) noexcept {
  // The integration runs on local copies, written back at the end: with nothing the loop stores
  // able to alias the command or the state, the state stays in registers instead of going
  // through memory on every substep's dependency chain. Same arithmetic, same results.
  const MotorCommand c = command;
  MotorState s{position_, velocity_, torque_, false};
  bool any_limit = false;
  if (c.drive == MotorDrive::unpowered) dt = std::min(dt, kMotorSubstepNs);  // nothing moves: one step does
  while (dt > 0) {
    const hal::Nanoseconds h = std::min(dt, kMotorSubstepNs);
    if (rests_under(c, h)) {
      // At rest (a joint held still): substep() is a pure function of the state, the command
      // and h, and left this state bit for bit unchanged under this command with a step of
      // rest_.h. With a step no longer than that it does too: every increment it adds is then
      // no larger, so it vanishes in the same roundings; the limit flags do not depend on h.
      // So this and every later (never longer) substep would change nothing.
      any_limit = any_limit || rest_.limited;
      break;
    }
    const MotorState before = s;
    s.limited = false;
    substep(c, static_cast<double>(h) * 1e-9, s);
    any_limit = any_limit || s.limited;
    dt -= h;
    if (bits_of(s.position) == bits_of(before.position) && bits_of(s.velocity) == bits_of(before.velocity) &&
        bits_of(s.torque) == bits_of(before.torque)) {
      rest_ = Rest{true, c, h, s.limited};
    } else {
      rest_.known = false;
    }
  }
  position_ = s.position;
  velocity_ = s.velocity;
  torque_ = s.torque;
  limited_ = any_limit;
}

void JointMotorModel::substep(const MotorCommand& c, double dt, MotorState& s) const noexcept {
  if (c.drive == MotorDrive::unpowered) {
    // Self-locking worm gear: no back-driving, the joint stands still.
    s.velocity = 0.0;
    s.torque = 0.0;
    return;
  }
  const double torque_limit = std::min(std::max(c.torque_limit_nm, 0.0), limits_.torque_max_nm);
  const double velocity_limit = std::min(std::max(c.velocity_limit_rad_s, 0.0), limits_.velocity_max_rad_s);
  double velocity_target = 0.0;
  double torque = 0.0;
  switch (c.drive) {
    case MotorDrive::position: {
      double target = c.position_rad;
      if (!limits_.continuous) target = std::max(limits_.position_min_rad, std::min(limits_.position_max_rad, target));
      if (target != c.position_rad) s.limited = true;
      velocity_target = kPositionGain * (target - s.position) + c.velocity_rad_s;
      break;
    }
    case MotorDrive::velocity: velocity_target = c.velocity_rad_s; break;
    case MotorDrive::braking: {
      // Quick-stop ramp: the largest deceleration the torque allows, to standstill.
      const double decel = torque_limit / inertia_;
      const double dv = std::min(std::fabs(s.velocity), decel * dt);
      s.velocity -= std::copysign(dv, s.velocity);
      s.torque = s.velocity == 0.0 ? 0.0 : -std::copysign(decel * inertia_, s.velocity);
      s.position += s.velocity * dt;
      return;
    }
    case MotorDrive::torque: torque = c.torque_nm; break;
    case MotorDrive::unpowered: break;
  }
  if (c.drive != MotorDrive::torque) {
    if (std::fabs(velocity_target) > velocity_limit) s.limited = true;
    velocity_target = clamp(velocity_target, velocity_limit);
    torque = inertia_ * kVelocityGain * (velocity_target - s.velocity);
  }
  if (std::fabs(torque) > torque_limit) s.limited = true;
  torque = clamp(torque, torque_limit);
  s.velocity += torque / inertia_ * dt;
  if (std::fabs(s.velocity) > velocity_limit) {
    // The drive's speed limiter (torque mode included): the internal limit is active.
    s.velocity = clamp(s.velocity, velocity_limit);
    s.limited = true;
  }
  s.position += s.velocity * dt;
  if (!limits_.continuous && (s.position < limits_.position_min_rad || s.position > limits_.position_max_rad)) {
    // A joint end stop: the joint stops at its limit.
    s.position = std::max(limits_.position_min_rad, std::min(limits_.position_max_rad, s.position));
    s.velocity = 0.0;
    s.limited = true;
  }
  s.torque = torque;
}

std::int32_t JointMotorModel::position_counts() const noexcept {
  // Wrap like a 32-bit modulo encoder counter (continuous joints run past the int32 range).
  const double counts = inline_math::nearbyint(position_ * drivers::kCountsPerRad);
  // fmod(x, 2^32) is x itself inside +-2^32 (every joint but a long-running track): skip the call.
  const double wrapped = std::fabs(counts) < kTwoTo32 ? counts : std::fmod(counts, kTwoTo32);
  const auto raw = static_cast<std::int64_t>(wrapped);
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(static_cast<std::uint64_t>(raw)));
}

std::int32_t JointMotorModel::velocity_counts_s() const noexcept {
  return static_cast<std::int32_t>(inline_math::nearbyint(velocity_ * drivers::kCountsPerRad));
}

std::int16_t JointMotorModel::torque_per_mille() const noexcept {
  const double permille = 1000.0 * torque_ / limits_.rated_torque_nm;
  return static_cast<std::int16_t>(inline_math::nearbyint(clamp(permille, 32767.0)));
}

MotorLimits motor_limits_of(std::size_t joint) noexcept {
  const JointInfo& j = kJoints[joint];
  MotorLimits m;
  m.velocity_max_rad_s = j.limits.velocity_max_rad_s;
  m.torque_max_nm = j.limits.torque_max_nm;
  m.rated_torque_nm = j.rated_torque_nm;
  m.position_min_rad = j.limits.position_min_rad;
  m.position_max_rad = j.limits.position_max_rad;
  m.continuous = j.continuous;
  return m;
}

}  // namespace rescue::drivers
