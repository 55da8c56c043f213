#include "core/kinematics/rescue_motion.hpp"

#include <algorithm>

#include "core/kinematics/forward_kinematics.hpp"

namespace rescue::kin {

const char* to_string(RescuePhase phase) noexcept {
  switch (phase) {
    case RescuePhase::lowering: return "lowering";
    case RescuePhase::forwarding: return "forwarding";
    case RescuePhase::backwarding: return "backwarding";
    case RescuePhase::done: return "done";
  }
  return "unknown";
}

JointVector ready_posture() noexcept {
  JointVector q = JointVector::Zero();
  const auto set = [&q](const char* name, double value) {
    q(static_cast<Eigen::Index>(joint_index(name))) = value;
  };
  // Upper arms down, elbows at a right angle: forearms and palms level, pointing forward.
  set("l_shoulder_roll", 0.1);
  set("r_shoulder_roll", -0.1);
  set("l_elbow", 1.5707963267948966);
  set("r_elbow", 1.5707963267948966);
  set("l_hand", 0.2);
  set("r_hand", 0.2);
  return q;
}

RescueMotion::RescueMotion(const JointVector& q_start, const RescueMotionConfig& config) noexcept : config_(config) {
  LinkPoses poses;
  forward_kinematics(q_start, poses);
  const Vector3 offsets[3] = {config.lowered, config.forwarded, config.lifted};
  left_[0] = poses[kLeftEe];
  right_[0] = poses[kRightEe];
  for (std::size_t k = 0; k < 3; ++k) {
    const Vector3 mirrored(offsets[k].x(), -offsets[k].y(), offsets[k].z());
    left_[k + 1] = Pose{left_[0].R, left_[0].p + offsets[k]};
    right_[k + 1] = Pose{right_[0].R, right_[0].p + mirrored};
  }
}

double RescueMotion::duration_s() const noexcept {
  return config_.phase_s[0] + config_.phase_s[1] + config_.phase_s[2];
}

double RescueMotion::distance_to_path(int arm, const Vector3& position) const noexcept {
  const std::array<Pose, 4>& waypoints = arm == 0 ? left_ : right_;
  double nearest = (position - waypoints[0].p).norm();
  for (std::size_t k = 0; k < 3; ++k) {
    const Vector3 from = waypoints[k].p;
    const Vector3 along = waypoints[k + 1].p - from;
    const double length2 = along.squaredNorm();
    const double s = length2 > 0.0 ? std::clamp((position - from).dot(along) / length2, 0.0, 1.0) : 0.0;
    nearest = std::min(nearest, (position - (from + s * along)).norm());
  }
  return nearest;
}

RescueSample RescueMotion::sample(double t_s) const noexcept {
  RescueSample out;
  double start = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const double length = config_.phase_s[k];
    if (t_s < start + length) {
      const MinimumJerkProfile profile = minimum_jerk((t_s - start) / length);
      const double s = profile.s;
      out.left = interpolate_pose(left_[k], left_[k + 1], s);
      out.right = interpolate_pose(right_[k], right_[k + 1], s);
      out.left_twist = interpolation_twist(left_[k], left_[k + 1], profile.ds / length);
      out.right_twist = interpolation_twist(right_[k], right_[k + 1], profile.ds / length);
      out.phase = static_cast<RescuePhase>(k);
      out.payload_kg = k == 2 ? s * config_.person_kg : 0.0;
      return out;
    }
    start += length;
  }
  out.left = left_[3];
  out.right = right_[3];
  out.phase = RescuePhase::done;
  out.payload_kg = config_.person_kg;
  return out;
}

}  // namespace rescue::kin
