#include "core/kinematics/joint_space_teleop.hpp"

#include <algorithm>

namespace rescue::kin {

// Fixed-size Eigen vectors are passed by reference (Eigen's own rule: no by-value alignment issues), so
// modernize-pass-by-value does not apply.
// NOLINTNEXTLINE(modernize-pass-by-value)
JointSpaceTeleop::JointSpaceTeleop(const JointVector& q_start, double dt_s) noexcept
    : references_(q_start), dt_s_(dt_s) {}

Status JointSpaceTeleop::step(const JointVector& velocity_command, JointMask out_of_service) noexcept {
  if (!velocity_command.allFinite()) return make_error(Errc::invalid_argument, "velocity command is not finite");
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((out_of_service & joint_bit(j)) != 0) continue;
    const JointLimits& lim = kJoints[j].limits;
    const auto row = static_cast<Eigen::Index>(j);
    const double v = std::clamp(velocity_command(row), -lim.velocity_max_rad_s, lim.velocity_max_rad_s);
    double next = references_(row) + v * dt_s_;
    if (!kJoints[j].continuous) next = std::clamp(next, lim.position_min_rad, lim.position_max_rad);
    references_(row) = next;
  }
  return Status::success();
}

void JointSpaceTeleop::take_ownership(const JointVector& current_references) noexcept {
  references_ = current_references;
  owns_motion_ = true;
}

}  // namespace rescue::kin
