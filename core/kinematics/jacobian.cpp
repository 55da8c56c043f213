#include "core/kinematics/jacobian.hpp"

namespace rescue::kin {
void frame_jacobian(const LinkPoses& poses, std::size_t frame, IkJacobian6& jacobian) noexcept {
  const Vector3& tip = poses[frame].p;
  for (std::size_t c = 0; c < kIkLink.size(); ++c) {
    const std::size_t link = kIkLink[c];
    const auto col = static_cast<Eigen::Index>(c);
    // The joint's link is the ancestor asked about (not swapped).
    // NOLINTNEXTLINE(readability-suspicious-call-argument)
    if (!is_ancestor_or_self(link, frame)) {
      jacobian.col(col).setZero();
      continue;
    }
    const Vector3 w = joint_axis(poses[link], link);
    jacobian.col(col).head<3>() = w.cross(tip - poses[link].p);
    jacobian.col(col).tail<3>() = w;
  }
}

void chain_jacobian(const Chain& chain, const ArmVector& q, ArmJacobian& jacobian, Pose& tip) noexcept {
  ChainPoses poses;
  tip = chain_poses(chain, q, poses);
  Eigen::Index col = 0;
  for (std::size_t k = 0; k < chain.size && col < kArmJoints; ++k) {
    const std::size_t link = chain.links[k];
    if (kLinkJoint[link] == kNoIndex) continue;
    const Vector3 w = joint_axis(poses[k], link);
    jacobian.col(col).head<3>() = w.cross(tip.p - poses[k].p);
    jacobian.col(col).tail<3>() = w;
    ++col;
  }
}

}  // namespace rescue::kin
