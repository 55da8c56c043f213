#include "core/kinematics/rc_period.hpp"

#include <algorithm>
#include <cmath>

#include "core/kinematics/jacobian.hpp"
#include "core/kinematics/palm_stopping.hpp"

namespace rescue::kin {

namespace {
// Share of the stopping budget the speed cap plans for: the held joints each brake at their own
// limit along a Jacobian that changes as they move, and the cut may come a period after the cap was
// computed, so the stop measured runs a little over the first-order bound (docs/kinematics.md).
constexpr double kStopBudgetShare = 0.8;
}  // namespace

RcPeriod::RcPeriod(const JointVector& q_start, const IkSettings& ik, const RescueMotionConfig& motion,
                   double damaged_palm_stop_budget_m) noexcept
    : ik_(ik), motion_(q_start, motion), teleop_(q_start, ik.dt_s), next_(q_start), wanted_(q_start),
      limiter_(q_start, ik.dt_s), lost_(analyse_lost_capability(q_start, 0)),
      stop_budget_m_(damaged_palm_stop_budget_m) {
  for (std::size_t arm = 0; arm < 2; ++arm) {
    const JointMask cut = joints_lost_by_link_failure_at(joint_index(arm == 0 ? "l_elbow" : "r_elbow"));
    held_if_cut_[arm] = task_shape_for(cut).held;
    braking_if_cut_[arm] = held_if_cut_[arm] & ~joint_bit(kIkJoints[0]);
  }
}

double RcPeriod::palm_stop_scale(const JointVector& q, JointMask locked, double scale) const noexcept {
  const double dt = ik_.settings().dt_s;
  const double budget = kStopBudgetShare * stop_budget_m_;
  double allowed = scale;
  for (std::size_t arm = 0; arm < 2; ++arm) {
    if (!shape_.palm_active[arm]) continue;
    IkJacobian6 jacobian;
    frame_jacobian(ik_.input_poses(), arm == 0 ? kLeftEe : kRightEe, jacobian);
    // The palm's speed from the joints the cut would leave held: the part that moves with the factor
    // (the step's joints) and the part that does not (held joints already braking).
    Vector3 fixed = Vector3::Zero();
    Vector3 per_scale = Vector3::Zero();
    for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
      const std::size_t j = kIkJoints[c];
      if ((held_if_cut_[arm] & joint_bit(j)) == 0) continue;
      const auto row = static_cast<Eigen::Index>(j);
      const Vector3 column = jacobian.block<3, 1>(0, static_cast<Eigen::Index>(c));
      if ((locked & joint_bit(j)) != 0) {
        fixed += column * limiter_.velocity()(row);
      } else {
        per_scale += column * ((next_(row) - q(row)) / dt);
      }
    }
    // The travel grows with the square of the speed: one pass is exact when nothing is braking.
    double s = allowed;
    for (int pass = 0; pass < 3; ++pass) {
      const double travel = least_palm_stopping_travel(jacobian, fixed + s * per_scale, braking_if_cut_[arm]);
      if (travel <= budget) break;
      s *= std::sqrt(budget / travel);
    }
    allowed = std::min(allowed, s);
  }
  return allowed;
}

RcPeriod::ScaleRange RcPeriod::feasible_range(const JointVector& q, JointMask locked) const noexcept {
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
  return ScaleRange{low, high};
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
    stop_budget_scale_ = 1.0;
    if (!collision_stop_.stop) {
      const ScaleRange range = feasible_range(q, locked);
      // No factor fits every joint: the largest that fits the slowing joints, the limiter clips the rest.
      scale_ = range.low <= range.high ? range.high : std::clamp(range.high, 0.0, 1.0);
      // The stopping budget slows the motion down, never faster than the joints can brake.
      stop_budget_scale_ = palm_stop_scale(q, locked, scale_);
      if (stop_budget_scale_ < scale_) scale_ = std::max(stop_budget_scale_, range.low <= range.high ? range.low : 0.0);
    }
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
