// One RC period of both RC tasks, as the RC task processes run it (design brief section 3): the
// rescue task samples the rescue motion, takes one task-priority IK step from the references it sent
// last period and writes the new ones; the joint-space teleoperation task computes its own
// references in the same period.
//
// After damage (docs/kinematics.md "After damage"): when the set of joints out of service changes,
// the task stack is reshaped (kin::TaskShape: a damaged arm's palm leaves the main task, its healthy
// joints and the waist brake to rest and hold) and the lost capability is analysed once (an SVD per
// arm) for the operator's view.
//
// Path-preserving limits: the IK's step is one direction in joint space for every joint at once. It
// is scaled by one factor (the largest in [0, 1] that keeps every moving joint within its speed,
// acceleration and position-braking limits) and the motion's own clock advances by that factor: the
// whole motion slows down where the limits bind instead of joints being clipped one by one, so the
// palms stay on their paths. Only when no factor fits (the limits of two joints contradict each
// other) does the acceleration limiter clip joints; those periods are counted.
//
// A stopping budget for the palms (docs/kinematics.md "After damage"): should an arm be cut at its
// elbow in any period, its held joints brake to rest at their acceleration limits and the palm, which
// may carry the person, travels on. The same factor is capped so that each palm in the main task
// could be stopped by the joints its arm would keep within the budget
// (`damaged_palm_stop_budget_m`; the bound of kin::least_palm_stopping_travel): the
// motion slows down where the palms move fast for their arms' braking, the palms stay on their paths
// and only arrive later.
#pragma once

#include <cstdint>

#include "core/kinematics/acceleration_limiter.hpp"
#include "core/kinematics/joint_space_teleop.hpp"
#include "core/kinematics/lost_capability.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/kinematics/task_priority_ik.hpp"
#include "core/kinematics/task_shape.hpp"

namespace rescue::kin {

// The stopping budget of a palm whose arm is cut, m (the firmware passes config::kDamagedPalmStopBudgetM).
inline constexpr double kDefaultDamagedPalmStopBudgetM = 0.005;

class RcPeriod {
 public:
  explicit RcPeriod(const JointVector& q_start, const IkSettings& ik = IkSettings{},
                    const RescueMotionConfig& motion = RescueMotionConfig{},
                    double damaged_palm_stop_budget_m = kDefaultDamagedPalmStopBudgetM) noexcept;

  // Period at wall time t_s since the motion started (the motion's own time never runs ahead of it);
  // `teleop_velocity` is the operator's joint-space command.
  Result<IkStepReport> run(double t_s, JointMask out_of_service, const JointVector& teleop_velocity) noexcept;

  // The references sent this period (after every limit) and their speeds.
  const JointVector& rescue_references() const noexcept { return limiter_.position(); }
  const JointVector& rescue_velocities() const noexcept { return limiter_.velocity(); }
  const JointVector& teleop_references() const noexcept { return teleop_.references(); }
  JointSpaceTeleop& teleop() noexcept { return teleop_; }
  const RescueMotion& motion() const noexcept { return motion_; }
  const RescueSample& last_sample() const noexcept { return sample_; }
  const LostCapability& lost_capability() const noexcept { return lost_; }
  JointMask out_of_service() const noexcept { return out_of_service_; }
  const TaskShape& shape() const noexcept { return shape_; }

  // Stopped for self-collision (the IK's clearance sub-task could not keep a pair apart): the motion
  // no longer advances, every joint comes to rest within its limits; the report of the stop.
  bool collision_stopped() const noexcept { return collision_stop_.stop; }
  const SelfCollisionReport& collision_stop() const noexcept { return collision_stop_; }
  // The smallest distance of a close pair seen (pairs within the activation distance; none: false).
  bool close_pair_seen() const noexcept { return close_pair_seen_; }
  double min_clearance_m() const noexcept { return min_clearance_m_; }

  double motion_time_s() const noexcept { return motion_time_s_; }
  double time_scale() const noexcept { return scale_; }              // this period's factor
  // The largest factor the palms' stopping budget allowed this period (1: no cap).
  double stop_budget_scale() const noexcept { return stop_budget_scale_; }
  std::uint64_t clipped_periods() const noexcept { return clipped_; }  // periods a joint was clipped alone
  // The palm's distance from its planned path, from the FK of the references sent last period (the
  // IK's input): what the robot was commanded, not what the IK planned.
  double path_deviation_m(int arm) const noexcept { return path_deviation_m_[static_cast<std::size_t>(arm)]; }
  const Vector3& commanded_palm(int arm) const noexcept { return palm_[static_cast<std::size_t>(arm)]; }

 private:
  struct ScaleRange {
    double low;   // the least factor every moving joint can brake to
    double high;  // the largest every moving joint can reach
  };
  ScaleRange feasible_range(const JointVector& q, JointMask locked) const noexcept;
  // The largest factor up to `scale` at which every palm in the main task keeps its stopping budget
  // should its arm be cut at the elbow (from the Jacobians at q, the IK's last input).
  double palm_stop_scale(const JointVector& q, JointMask locked, double scale) const noexcept;

  TaskPriorityIk ik_;
  RescueMotion motion_;
  JointSpaceTeleop teleop_;
  JointVector next_;
  JointVector wanted_;
  AccelerationLimiter limiter_;
  RescueSample sample_;
  LostCapability lost_;
  TaskShape shape_{};
  JointMask out_of_service_{0};
  SelfCollisionReport collision_stop_{};
  bool close_pair_seen_{false};
  double min_clearance_m_{0.0};
  double motion_time_s_{0.0};
  double scale_{1.0};
  double stop_budget_scale_{1.0};
  double stop_budget_m_;
  // Per arm (0 left, 1 right), after a cut at its elbow: the joints the task holds (kin::TaskShape)
  // and those of them counted as braking its palm (the waist left out: the bound the damage test checks).
  std::array<JointMask, 2> held_if_cut_{};
  std::array<JointMask, 2> braking_if_cut_{};
  std::uint64_t clipped_{0};
  std::array<double, 2> path_deviation_m_{};
  std::array<Vector3, 2> palm_{Vector3::Zero(), Vector3::Zero()};
};

}  // namespace rescue::kin
