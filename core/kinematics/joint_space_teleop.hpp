// The second RC task: joint-space teleoperation. Every period it integrates the operator's joint
// velocity commands into its own reference space (clamped to each joint's velocity and position
// limits, reached and left at most at its acceleration limit, braking before a position limit;
// joints out of service held), whether or not it owns the motion. When the operator hands
// it the motion, it first takes over the references being sent (bumpless), so ownership changes
// never make the robot jump.
#pragma once

#include "core/kinematics/kinematic_model.hpp"
#include "core/base/result.hpp"

namespace rescue::kin {

class JointSpaceTeleop {
 public:
  explicit JointSpaceTeleop(const JointVector& q_start, double dt_s = 0.001) noexcept;

  // One period with the operator's velocities (rad/s, kJoints order). Tracks are velocity-controlled
  // and continuous: their reference integrates without position limits.
  // Errors: invalid_argument for a non-finite command (the references are left unchanged).
  Status step(const JointVector& velocity_command, JointMask out_of_service) noexcept;

  // The operator gives this task the motion: it continues from `current_references` (the owner's)
  // and their speeds `current_velocities` (default: at rest): with no command its joints then brake
  // from that speed at their acceleration limits, they never stop dead.
  void take_ownership(const JointVector& current_references) noexcept;
  void take_ownership(const JointVector& current_references, const JointVector& current_velocities) noexcept;
  void release_ownership() noexcept { owns_motion_ = false; }
  bool owns_motion() const noexcept { return owns_motion_; }

  const JointVector& references() const noexcept { return references_; }

 private:
  JointVector references_;
  JointVector velocities_;  // last period's, for the acceleration limits
  double dt_s_;
  bool owns_motion_{false};
};

}  // namespace rescue::kin
