// Forward kinematics: the pose of every link of the robot in base_link, and the poses along one
// chain (an arm) for that chain's joint values. Each link is its parent's pose, moved by the
// joint origin (no rotation, checked by the generator) and turned about the joint's axis
// (+-x, +-y or +-z), so a joint costs one sincos and two column updates instead of a 3x3 product.
#pragma once

#include <array>
#include <utility>

#include "core/kinematics/kinematic_model.hpp"
#include "core/kinematics/pose.hpp"
#include "core/kinematics/sincos.hpp"

namespace rescue::kin {

using LinkPoses = std::array<Pose, kLinkCount>;
using ChainPoses = std::array<Pose, kMaxChainLinks>;

// Pose of link `link` from its parent's pose and its joint's sin/cos (ignored for fixed links).
inline void place_link(const Pose& parent, std::size_t link, const SinCos& sc, Pose& out) noexcept {
  const desc::Link& d = desc::kLinks[link];
  out.p = parent.p + parent.R.col(0) * d.origin[0] + parent.R.col(1) * d.origin[1] + parent.R.col(2) * d.origin[2];
  if (d.type == desc::JointType::fixed) {
    out.R = parent.R;
    return;
  }
  const double s = d.axis_sign * sc.s;
  const double c = sc.c;
  // R * Rot_axis(angle): the two columns other than the axis turn, the axis column stays.
  const int a = d.axis;
  const int i = (a + 1) % 3;
  const int k = (a + 2) % 3;
  out.R.col(a) = parent.R.col(a);
  out.R.col(i) = c * parent.R.col(i) + s * parent.R.col(k);
  out.R.col(k) = c * parent.R.col(k) - s * parent.R.col(i);
}

// The same with the link known at compile time: axis, sign, origin and kind become constants,
// so each joint is straight-line code (used to unroll the arm chains and the whole tree).
template <std::size_t Link>
inline void place_link_static(const Pose& parent, const SinCos& sc, Pose& out) noexcept {
  constexpr desc::Link d = desc::kLinks[Link];
  out.p = parent.p;
  if constexpr (d.origin[0] != 0.0) out.p += parent.R.col(0) * d.origin[0];
  if constexpr (d.origin[1] != 0.0) out.p += parent.R.col(1) * d.origin[1];
  if constexpr (d.origin[2] != 0.0) out.p += parent.R.col(2) * d.origin[2];
  if constexpr (d.type == desc::JointType::fixed) {
    out.R = parent.R;
  } else {
    constexpr int a = d.axis;
    constexpr int i = (a + 1) % 3;
    constexpr int k = (a + 2) % 3;
    const double s = d.axis_sign * sc.s;
    const double c = sc.c;
    out.R.col(a) = parent.R.col(a);
    out.R.col(i) = c * parent.R.col(i) + s * parent.R.col(k);
    out.R.col(k) = c * parent.R.col(k) - s * parent.R.col(i);
  }
}

// The joint angles' sin/cos are computed in a pass of their own before the poses are chained:
// they do not depend on each other, so the CPU overlaps them instead of waiting on each in turn.

// Every link's pose in base_link (base_link itself is the identity).
void forward_kinematics(const JointVector& q, LinkPoses& poses) noexcept;

// Poses of the chain's links (chain order) for the chain's own joint values, base side first.
// Returns the tip's pose.
Pose chain_poses(const Chain& chain, const ArmVector& q, ChainPoses& poses) noexcept;
// The tip's pose only.
Pose chain_tip_pose(const Chain& chain, const ArmVector& q) noexcept;

// The chain's joint values taken out of a whole-robot vector, and back.
ArmVector chain_joint_values(const Chain& chain, const JointVector& q) noexcept;

}  // namespace rescue::kin
