#include "core/kinematics/rc_period.hpp"

#include <algorithm>
#include <cmath>

namespace rescue::kin {

RcPeriod::RcPeriod(const JointVector& q_start, const IkSettings& ik, const RescueMotionConfig& motion) noexcept
    : ik_(ik), motion_(q_start, motion), teleop_(q_start, ik.dt_s), next_(q_start), wanted_(q_start),
      limiter_(q_start, ik.dt_s), lost_(analyse_lost_capability(q_start, 0)) {}

double RcPeriod::feasible_scale(const JointVector& q, JointMask locked) const noexcept {
  const double dt = ik_.settings().dt_s;
  double low = 0.0;
  double high = 1.0;
  for (const std::size_t j : kIkJoints) {
    if ((locked & joint_bit(j)) != 0) continue;
    const auto row = static_cast<Eigen::Index>(j);
    const JointLimits& lim = kJoints[j].limits;
    const double a_max = kJointAcceleration[j];
    const double v0 = limiter_.velocity()(row);
    // The speeds this joint may take this period (the limiter's own interval).
    const double v_low = std::max({v0 - a_max * dt, -lim.velocity_max_rad_s,
                                   -braking_speed(std::max(0.0, q(row) - lim.position_min_rad), a_max, dt)});
    const double v_high = std::min({v0 + a_max * dt, lim.velocity_max_rad_s,
                                    braking_speed(std::max(0.0, lim.position_max_rad - q(row)), a_max, dt)});
    const double p = (next_(row) - q(row)) / dt;  // the step's speed at factor 1
    if (std::fabs(p) < 1e-12) continue;          // no factor changes this joint's speed
    const double a = v_low / p;
    const double b = v_high / p;
    low = std::max(low, std::min(a, b));
    high = std::min(high, std::max(a, b));
  }
  // No factor fits every joint: the largest that fits the slowing joints, the limiter clips the rest.
  return low <= high ? high : std::clamp(high, 0.0, 1.0);
}

Result<IkStepReport> RcPeriod::run(double t_s, JointMask out_of_service, const JointVector& teleop_velocity) noexcept {
  if (out_of_service != out_of_service_) {
    out_of_service_ = out_of_service;
    shape_ = task_shape_for(out_of_service);
    lost_ = analyse_lost_capability(limiter_.position(), out_of_service);
  }
  const double dt = ik_.settings().dt_s;
  sample_ = motion_.sample(motion_time_s_);
  IkTargets targets{sample_.left, sample_.right, sample_.payload_kg, shape_.palm_active};
  targets.left_twist = sample_.left_twist;
  targets.right_twist = sample_.right_twist;
  // The IK steps from what was sent (the limiter's references), so every figure it reports is the
  // commanded robot's.
  const JointVector& q = limiter_.position();
  const JointMask locked = out_of_service | shape_.held;
  Result<IkStepReport> report = ik_.step(q, targets, locked, next_);
  wanted_ = q;
  scale_ = 0.0;
  if (report.ok()) {
    for (int arm = 0; arm < 2; ++arm) {
      palm_[static_cast<std::size_t>(arm)] = report.value().palm_position[arm];
      path_deviation_m_[static_cast<std::size_t>(arm)] = motion_.distance_to_path(arm, palm_[static_cast<std::size_t>(arm)]);
    }
    const SelfCollisionReport& collision = report.value().self_collision;
    if (collision.close_pairs > 0) {
      min_clearance_m_ = close_pair_seen_ ? std::min(min_clearance_m_, collision.closest_distance_m) : collision.closest_distance_m;
      close_pair_seen_ = true;
    }
    // The last resort: a pair closer than the stop distance stops the motion for good (every joint
    // to rest within its limits; the operator sees the reason).
    if (collision.stop && !collision_stop_.stop) collision_stop_ = collision;
    scale_ = collision_stop_.stop ? 0.0 : feasible_scale(q, locked);
    for (const std::size_t j : kIkJoints) {
      if ((locked & joint_bit(j)) != 0) continue;
      const auto row = static_cast<Eigen::Index>(j);
      wanted_(row) = q(row) + scale_ * (next_(row) - q(row));
    }
  }
  limiter_.plan_from_references();
  (void)limiter_.step(wanted_, out_of_service, shape_.held);
  // Clipped: a joint the step moved ended elsewhere than the scaled step put it (beyond rounding).
  bool clipped = false;
  for (const std::size_t j : kIkJoints) {
    if ((locked & joint_bit(j)) != 0) continue;
    const auto row = static_cast<Eigen::Index>(j);
    clipped = clipped || std::fabs(limiter_.position()(row) - wanted_(row)) > 1e-12;
  }
  if (clipped) ++clipped_;
  // The motion's clock moves as far as the step did, never ahead of the wall clock.
  motion_time_s_ = std::min(motion_time_s_ + scale_ * dt, std::max(t_s, 0.0) + dt);
  const Status teleop_status = teleop_.step(teleop_velocity, out_of_service);
  if (!teleop_status.ok()) return teleop_status.error();
  return report;
}

}  // namespace rescue::kin
