// The last stage of every RC task's references: each joint follows what the task computed with its
// velocity and acceleration limits (kJoints velocity, the URDF's <limit acceleration>), so no
// reference the RC tasks write asks a drive for more.
//
// Per joint, every period: the wanted position x* and its rate v* (from the last wanted position);
// the velocity that closes the gap e = x* - x without overshoot, braking at a_max:
//   v_d = v* + sign(e) min(braking_speed(|e|), |e| / dt)      (about sqrt(2 a_max |e|))
// then v = v_d clamped to [v - a_max dt, v + a_max dt] and to [-v_max, v_max], x += v dt, clamped to
// the position limits. A wanted motion within the limits (the rescue motion's trajectory) passes
// unchanged (e stays 0); a jump (a new target, a mode change) becomes a ramp. Joints out of service
// hold where they are, with zero velocity (they are not commanded). Pure computation, fixed size.
#pragma once

#include <cmath>

#include "core/kinematics/kinematic_model.hpp"

namespace rescue::kin {

// The highest speed from which a joint stops within `distance` braking at `a_max`, in periods of
// dt: n whole steps of a_max dt less each cover a_max dt^2 n (n + 1) / 2; what is left of the
// distance is spread evenly over those n + 1 periods (less than a_max dt more each), so the speed
// falls by exactly a_max dt per period (the continuous sqrt(2 a d) would ask for more than a_max
// in the last periods).
inline double braking_speed(double distance, double a_max, double dt_s) noexcept {
  const double step = a_max * dt_s;
  const double n = std::floor(std::sqrt(0.25 + 2.0 * distance / (step * dt_s)) - 0.5);
  const double left = distance - step * dt_s * n * (n + 1.0) / 2.0;
  return step * n + left / ((n + 1.0) * dt_s);
}

class AccelerationLimiter {
 public:
  AccelerationLimiter(const JointVector& start, double dt_s) noexcept;

  // Restarts at `position` at rest (a new owner of the motion, a restart).
  void reset(const JointVector& position) noexcept;

  // One period towards `wanted`; returns the references.
  const JointVector& step(const JointVector& wanted, JointMask out_of_service) noexcept;

  const JointVector& position() const noexcept { return position_; }
  const JointVector& velocity() const noexcept { return velocity_; }
  // Joints whose wanted motion was beyond a limit last period (the references lag it).
  JointMask limited() const noexcept { return limited_; }

 private:
  double dt_s_;
  JointVector position_;
  JointVector velocity_;
  JointVector last_wanted_;
  JointMask limited_{0};
};

}  // namespace rescue::kin
