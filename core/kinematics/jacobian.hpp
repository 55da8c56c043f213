// Geometric Jacobians (base_link frame, reference point at the frame's origin): rows
// [linear velocity; angular velocity], one column per joint. For a revolute joint with axis w
// through p_j, the column of frame F is [w x (p_F - p_j); w], and zero when the joint does not
// move F. Two forms: over the RC task's 13 IK joints from whole-robot link poses, and over one
// 7-joint arm chain from its own joint values (the kernel compared with KDL's ChainJntToJacSolver).
#pragma once

#include "core/kinematics/forward_kinematics.hpp"

namespace rescue::kin {

// True when `ancestor` is `descendant` or lies on the path from base_link to it.
constexpr bool is_ancestor_or_self(std::size_t ancestor, std::size_t descendant) {
  while (descendant != kNoIndex) {
    if (descendant == ancestor) return true;
    const int parent = desc::kLinks[descendant].parent;
    descendant = parent < 0 ? kNoIndex : static_cast<std::size_t>(parent);
  }
  return false;
}

// Unit axis of the joint moving `link`, in base_link, from the link's pose.
inline Vector3 joint_axis(const Pose& link_pose, std::size_t link) noexcept {
  const desc::Link& d = desc::kLinks[link];
  return d.axis_sign * link_pose.R.col(d.axis);
}

// Jacobian of the origin of link/frame `frame` over the IK joints.
void frame_jacobian(const LinkPoses& poses, std::size_t frame, IkJacobian6& jacobian) noexcept;

// Jacobian of a chain's tip over the chain's joints; `tip` receives the tip's pose.
void chain_jacobian(const Chain& chain, const ArmVector& q, ArmJacobian& jacobian, Pose& tip) noexcept;

}  // namespace rescue::kin
