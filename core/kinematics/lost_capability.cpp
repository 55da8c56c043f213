#include "core/kinematics/lost_capability.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cstdio>

#include "core/kinematics/forward_kinematics.hpp"
#include "core/kinematics/jacobian.hpp"

namespace rescue::kin {
namespace {

// Distance from the shoulder yaw joint (upper arm link's origin) to the wrist (wrist link's origin).
double wrist_distance(const JointVector& q, std::size_t upper_arm, std::size_t wrist) noexcept {
  LinkPoses poses;
  forward_kinematics(q, poses);
  return (poses[wrist].p - poses[upper_arm].p).norm();
}

}  // namespace

LostCapability analyse_lost_capability(const JointVector& q, JointMask out_of_service) noexcept {
  LinkPoses poses;
  forward_kinematics(q, poses);
  LostCapability result;
  const std::size_t frames[2] = {kLeftEe, kRightEe};
  for (std::size_t arm = 0; arm < 2; ++arm) {
    IkJacobian6 j;
    frame_jacobian(poses, frames[arm], j);
    for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
      if ((out_of_service & joint_bit(kIkJoints[c])) != 0) j.col(static_cast<Eigen::Index>(c)).setZero();
    }
    const Eigen::JacobiSVD<IkJacobian6> svd(j, Eigen::ComputeFullU);
    const auto& sigma = svd.singularValues();  // descending
    ArmCapability& cap = result.arms[arm];
    int rank = 0;
    for (Eigen::Index i = 0; i < sigma.size(); ++i) {
      if (sigma(i) > kLostSingularValue) rank = static_cast<int>(i) + 1;
    }
    cap.lost_directions = 6 - rank;
    cap.sigma_min = rank > 0 ? sigma(rank - 1) : 0.0;
    for (int k = 0; k < cap.lost_directions; ++k) cap.directions.col(k) = svd.matrixU().col(rank + k);
    for (int axis = 0; axis < 6; ++axis) {
      double share = 0.0;
      for (int k = 0; k < cap.lost_directions; ++k) share += cap.directions(axis, k) * cap.directions(axis, k);
      if (share > 0.5) cap.uncontrollable_axes = static_cast<std::uint8_t>(cap.uncontrollable_axes | (1U << axis));
    }
    constexpr std::size_t kElbow[2] = {joint_index("l_elbow"), joint_index("r_elbow")};
    constexpr std::size_t kUpperArm[2] = {link_index("l_upper_arm_link"), link_index("r_upper_arm_link")};
    constexpr std::size_t kWrist[2] = {link_index("l_wrist_link"), link_index("r_wrist_link")};
    const auto elbow = static_cast<Eigen::Index>(kElbow[arm]);
    cap.reach_fixed = (out_of_service & joint_bit(kElbow[arm])) != 0;
    cap.wrist_distance_m = (poses[kWrist[arm]].p - poses[kUpperArm[arm]].p).norm();
    JointVector bent = q;
    bent(elbow) = kJoints[kElbow[arm]].limits.position_min_rad;
    const double at_min = wrist_distance(bent, kUpperArm[arm], kWrist[arm]);
    bent(elbow) = kJoints[kElbow[arm]].limits.position_max_rad;
    const double at_max = wrist_distance(bent, kUpperArm[arm], kWrist[arm]);
    cap.wrist_distance_min_m = std::min(at_min, at_max);
    cap.wrist_distance_max_m = std::max(at_min, at_max);
  }
  return result;
}

void format_axes(std::uint8_t axes, char* out, std::size_t capacity) noexcept {
  if (capacity == 0) return;
  static const char* const kNames[6] = {"x", "y", "z", "rx", "ry", "rz"};
  std::size_t used = 0;
  out[0] = '\0';
  for (unsigned axis = 0; axis < 6; ++axis) {
    if ((axes & (1U << axis)) == 0 || used >= capacity) continue;
    const int n = std::snprintf(out + used, capacity - used, "%s%s", used == 0 ? "" : ",", kNames[axis]);
    if (n < 0) return;
    used += static_cast<std::size_t>(n);
  }
  if (used == 0) (void)std::snprintf(out, capacity, "none");
}

}  // namespace rescue::kin
