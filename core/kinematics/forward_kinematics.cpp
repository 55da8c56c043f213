#include "core/kinematics/forward_kinematics.hpp"

namespace rescue::kin {

void forward_kinematics(const JointVector& q, LinkPoses& poses) noexcept {
  poses[0] = Pose{};
  for (std::size_t i = 1; i < kLinkCount; ++i) {
    const std::size_t j = kLinkJoint[i];
    const double angle = j == kNoIndex ? 0.0 : q(static_cast<Eigen::Index>(j));
    place_link(poses[static_cast<std::size_t>(desc::kLinks[i].parent)], i, angle, poses[i]);
  }
}

Pose chain_poses(const Chain& chain, const ArmVector& q, ChainPoses& poses) noexcept {
  Pose parent{};
  Eigen::Index next = 0;
  for (std::size_t k = 0; k < chain.size; ++k) {
    const std::size_t link = chain.links[k];
    double angle = 0.0;
    if (kLinkJoint[link] != kNoIndex) angle = q(next++);
    place_link(parent, link, angle, poses[k]);
    parent = poses[k];
  }
  return parent;
}

Pose chain_tip_pose(const Chain& chain, const ArmVector& q) noexcept {
  Pose pose{};
  Pose next{};
  Eigen::Index joint = 0;
  for (std::size_t k = 0; k < chain.size; ++k) {
    const std::size_t link = chain.links[k];
    double angle = 0.0;
    if (kLinkJoint[link] != kNoIndex) angle = q(joint++);
    place_link(pose, link, angle, next);
    pose = next;
  }
  return pose;
}

ArmVector chain_joint_values(const Chain& chain, const JointVector& q) noexcept {
  ArmVector values = ArmVector::Zero();
  Eigen::Index next = 0;
  for (std::size_t k = 0; k < chain.size; ++k) {
    const std::size_t j = kLinkJoint[chain.links[k]];
    if (j != kNoIndex && next < kArmJoints) values(next++) = q(static_cast<Eigen::Index>(j));
  }
  return values;
}

}  // namespace rescue::kin
