// Forward kinematics equals Orocos KDL's ChainFkSolverPos_recursive to 1e-9 on thousands of random
// configurations of both 7-joint arm chains, for the tip and every intermediate frame; the
// whole-robot FK agrees with the chain FK.
#include <gtest/gtest.h>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <random>

#include "core/kinematics/forward_kinematics.hpp"
#include "tests/core/kinematics/kdl_chain.hpp"
#include "tests/core/kinematics/random_configurations.hpp"

namespace rescue::kin {
namespace {

constexpr int kConfigurations = 5000;
constexpr double kTolerance = 1e-9;

double difference(const Pose& a, const Pose& b) {
  return std::max((a.R - b.R).cwiseAbs().maxCoeff(), (a.p - b.p).cwiseAbs().maxCoeff());
}

void expect_chain_matches_kdl(const Chain& chain, std::uint64_t seed) {
  const KDL::Chain kdl = test::make_kdl_chain(chain);
  ASSERT_EQ(kdl.getNrOfJoints(), static_cast<unsigned>(kArmJoints));
  KDL::ChainFkSolverPos_recursive solver(kdl);
  std::mt19937_64 rng(seed);
  double worst = 0.0;
  for (int n = 0; n < kConfigurations; ++n) {
    const JointVector q_all = test::random_configuration(rng);
    const ArmVector q = chain_joint_values(chain, q_all);
    KDL::Frame frame;
    ASSERT_GE(solver.JntToCart(test::to_kdl(q), frame), 0);
    const Pose tip = chain_tip_pose(chain, q);
    worst = std::max(worst, difference(tip, test::to_pose(frame)));

    // Every moving link of the chain: KDL segment k + 1 ends at link k + 1's joint frame.
    ChainPoses poses;
    (void)chain_poses(chain, q, poses);
    for (std::size_t k = 0; k + 1 < static_cast<std::size_t>(kArmJoints); ++k) {
      ASSERT_GE(solver.JntToCart(test::to_kdl(q), frame, static_cast<int>(k) + 2), 0);
      worst = std::max(worst, (poses[k + 1].p - test::to_pose(frame).p).cwiseAbs().maxCoeff());
    }

    LinkPoses all;
    forward_kinematics(q_all, all);
    worst = std::max(worst, difference(all[chain.links[chain.size - 1]], tip));
  }
  EXPECT_LT(worst, kTolerance) << "worst difference " << worst;
}

TEST(ForwardKinematics, LeftArmMatchesKdlOnRandomConfigurations) { expect_chain_matches_kdl(kLeftArm, 1); }

TEST(ForwardKinematics, RightArmMatchesKdlOnRandomConfigurations) { expect_chain_matches_kdl(kRightArm, 2); }

TEST(ForwardKinematics, ZeroConfigurationPlacesLinksAtTheirUrdfOrigins) {
  LinkPoses poses;
  forward_kinematics(JointVector::Zero(), poses);
  for (std::size_t i = 1; i < kLinkCount; ++i) {
    const desc::Link& d = desc::kLinks[i];
    const Pose& parent = poses[static_cast<std::size_t>(d.parent)];
    EXPECT_TRUE(poses[i].R.isIdentity(0.0)) << d.name;
    EXPECT_TRUE(poses[i].p.isApprox(parent.p + Vector3(d.origin[0], d.origin[1], d.origin[2]))) << d.name;
  }
  // Arms hang down at q = 0: the palm is below the shoulder by the arm's length.
  EXPECT_NEAR(poses[kLeftEe].p.z(), 0.5 + 0.5 - (0.15 + 0.3 + 0.35 + 0.05 + 0.15), 1e-12);
}

}  // namespace
}  // namespace rescue::kin
