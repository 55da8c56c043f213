// One RC period of both RC tasks, as the RC task processes will run it (design brief section 3):
// the rescue task samples the rescue motion, takes one task-priority IK step from its last
// references and writes the new ones into its reference space; the joint-space teleoperation task
// computes its own references in the same period. When the set of joints out of service changes,
// the lost capability is analysed once (an SVD per arm) and kept for the operator's view.
// The IK steps from its own plan (the joints it computed last period); the rescue references are
// that plan through the acceleration limiter (unchanged while the plan is within the limits).
#pragma once

#include "core/kinematics/acceleration_limiter.hpp"
#include "core/kinematics/joint_space_teleop.hpp"
#include "core/kinematics/lost_capability.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/kinematics/task_priority_ik.hpp"

namespace rescue::kin {

class RcPeriod {
 public:
  explicit RcPeriod(const JointVector& q_start, const IkSettings& ik = IkSettings{},
           const RescueMotionConfig& motion = RescueMotionConfig{}) noexcept;

  // Period at time t_s of the motion; `teleop_velocity` is the operator's joint-space command.
  Result<IkStepReport> run(double t_s, JointMask out_of_service, const JointVector& teleop_velocity) noexcept;

  const JointVector& rescue_references() const noexcept { return limiter_.position(); }
  const JointVector& rescue_velocities() const noexcept { return limiter_.velocity(); }
  const JointVector& planned() const noexcept { return planned_; }  // the IK's joints before the limiter
  const JointVector& teleop_references() const noexcept { return teleop_.references(); }
  JointSpaceTeleop& teleop() noexcept { return teleop_; }
  const RescueMotion& motion() const noexcept { return motion_; }
  const RescueSample& last_sample() const noexcept { return sample_; }
  const LostCapability& lost_capability() const noexcept { return lost_; }
  JointMask out_of_service() const noexcept { return out_of_service_; }

 private:
  TaskPriorityIk ik_;
  RescueMotion motion_;
  JointSpaceTeleop teleop_;
  JointVector planned_;
  JointVector next_;
  AccelerationLimiter limiter_;
  RescueSample sample_;
  LostCapability lost_;
  JointMask out_of_service_{0};
};

}  // namespace rescue::kin
