#include "core/kinematics/forward_kinematics.hpp"

namespace rescue::kin {
namespace {

constexpr SinCos kFixed{0.0, 1.0};

// sin/cos of each chain link's joint (kFixed for fixed links).
void chain_sincos(const Chain& chain, const ArmVector& q, std::array<SinCos, kMaxChainLinks>& sc) noexcept {
  Eigen::Index joint = 0;
  for (std::size_t k = 0; k < chain.size; ++k) {
    sc[k] = kLinkJoint[chain.links[k]] == kNoIndex ? kFixed : sincos(q(joint++));
  }
}

// Whole tree, unrolled: link I (I >= 1) from its parent.
template <std::size_t... I>
void place_tree(const std::array<SinCos, kLinkCount>& sc, LinkPoses& poses, std::index_sequence<I...>) noexcept {
  (place_link_static<I + 1>(poses[static_cast<std::size_t>(desc::kLinks[I + 1].parent)], sc[I + 1], poses[I + 1]), ...);
}

// One arm chain, unrolled: link K of the chain from link K - 1 (or the root).
template <const Chain& C, std::size_t... K>
void place_chain(const std::array<SinCos, kMaxChainLinks>& sc, ChainPoses& poses, std::index_sequence<K...>) noexcept {
  const Pose root{};
  (place_link_static<C.links[K]>(K == 0 ? root : poses[K == 0 ? 0 : K - 1], sc[K], poses[K]), ...);
}

template <const Chain& C>
Pose arm_chain_poses(const ArmVector& q, ChainPoses& poses) noexcept {
  std::array<SinCos, kMaxChainLinks> sc;
  chain_sincos(C, q, sc);
  place_chain<C>(sc, poses, std::make_index_sequence<C.size>{});
  return poses[C.size - 1];
}

}  // namespace

void forward_kinematics(const JointVector& q, LinkPoses& poses) noexcept {
  std::array<SinCos, kLinkCount> sc;
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    const std::size_t j = kLinkJoint[i];
    sc[i] = j == kNoIndex ? kFixed : sincos(q(static_cast<Eigen::Index>(j)));
  }
  poses[0] = Pose{};
  place_tree(sc, poses, std::make_index_sequence<kLinkCount - 1>{});
}

Pose chain_poses(const Chain& chain, const ArmVector& q, ChainPoses& poses) noexcept {
  if (&chain == &kLeftArm) return arm_chain_poses<kLeftArm>(q, poses);
  if (&chain == &kRightArm) return arm_chain_poses<kRightArm>(q, poses);
  std::array<SinCos, kMaxChainLinks> sc;
  chain_sincos(chain, q, sc);
  const Pose root{};
  for (std::size_t k = 0; k < chain.size; ++k) place_link(k == 0 ? root : poses[k - 1], chain.links[k], sc[k], poses[k]);
  return chain.size == 0 ? root : poses[chain.size - 1];
}

Pose chain_tip_pose(const Chain& chain, const ArmVector& q) noexcept {
  ChainPoses poses;
  return chain_poses(chain, q, poses);
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
