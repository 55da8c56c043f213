#include "core/kinematics/joint_space_teleop.hpp"

#include "core/kinematics/acceleration_limiter.hpp"

#include <algorithm>
#include <cmath>

namespace rescue::kin {

// Fixed-size Eigen vectors are passed by reference (Eigen's own rule: no by-value alignment issues), so
// modernize-pass-by-value does not apply.
// NOLINTNEXTLINE(modernize-pass-by-value)
JointSpaceTeleop::JointSpaceTeleop(const JointVector& q_start, double dt_s) noexcept
    : references_(q_start), velocities_(JointVector::Zero()), dt_s_(dt_s) {}

Status JointSpaceTeleop::step(const JointVector& velocity_command, JointMask out_of_service) noexcept {
  if (!velocity_command.allFinite()) return make_error(Errc::invalid_argument, "velocity command is not finite");
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const auto row = static_cast<Eigen::Index>(j);
    if ((out_of_service & joint_bit(j)) != 0) {
      velocities_(row) = 0.0;
      continue;
    }
    const JointLimits& lim = kJoints[j].limits;
    // The command within the velocity limit, reached at most at the acceleration limit, and braking
    // at that limit so the joint stops at its position limit instead of hitting it.
    const double a_max = kJointAcceleration[j];
    double v = std::clamp(velocity_command(row), -lim.velocity_max_rad_s, lim.velocity_max_rad_s);
    if (!kJoints[j].continuous) {
      const double room = std::max(0.0, v > 0.0 ? lim.position_max_rad - references_(row) : references_(row) - lim.position_min_rad);
      const double stop = std::min(braking_speed(room, a_max, dt_s_), room / dt_s_);
      v = std::clamp(v, -stop, stop);
    }
    v = std::clamp(v, velocities_(row) - a_max * dt_s_, velocities_(row) + a_max * dt_s_);
    double next = references_(row) + v * dt_s_;
    if (!kJoints[j].continuous) next = std::clamp(next, lim.position_min_rad, lim.position_max_rad);
    velocities_(row) = (next - references_(row)) / dt_s_;
    references_(row) = next;
  }
  return Status::success();
}

void JointSpaceTeleop::take_ownership(const JointVector& current_references) noexcept {
  take_ownership(current_references, JointVector::Zero());
}

void JointSpaceTeleop::take_ownership(const JointVector& current_references, const JointVector& current_velocities) noexcept {
  references_ = current_references;
  velocities_ = current_velocities;
  owns_motion_ = true;
}

}  // namespace rescue::kin
