// Forward kinematics equals Orocos KDL on thousands of random configurations: KDL's tree and chains
// are built from the URDF file by kdl_parser (tests/core/kinematics/urdf_oracle.hpp), not from the
// generated description, so a mistake in the generator fails here. Every link of the whole robot
// equals TreeFkSolverPos_recursive and both palms ChainFkSolverPos_recursive to 1e-9; the chain FK
// equals the whole-robot FK; and a mutant URDF (an elbow axis tilted, a joint origin moved) makes the
// oracle disagree, which proves it reads the file.
#include <gtest/gtest.h>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <random>

#include "core/kinematics/forward_kinematics.hpp"
#include "tests/core/kinematics/random_configurations.hpp"
#include "tests/core/kinematics/urdf_oracle.hpp"

namespace rescue::kin {
namespace {

constexpr int kConfigurations = 2500;
constexpr double kTolerance = 1e-9;

double difference(const Pose& a, const Pose& b) {
  return std::max((a.R - b.R).cwiseAbs().maxCoeff(), (a.p - b.p).cwiseAbs().maxCoeff());
}

// Largest difference between our FK and the oracle's over every link and both palm chains.
double worst_difference(const test::UrdfOracle& oracle, std::uint64_t seed, int configurations) {
  const KDL::Chain chains[2] = {oracle.chain("l_ee"), oracle.chain("r_ee")};
  const Chain* ours[2] = {&kLeftArm, &kRightArm};
  std::mt19937_64 rng(seed);
  double worst = 0.0;
  for (int n = 0; n < configurations; ++n) {
    const JointVector q_all = test::random_configuration(rng);
    LinkPoses all;
    forward_kinematics(q_all, all);
    for (std::size_t i = 0; i < kLinkCount; ++i) {
      worst = std::max(worst, difference(all[i], oracle.link_pose(q_all, desc::kLinks[i].name)));
    }
    for (int arm = 0; arm < 2; ++arm) {
      EXPECT_EQ(chains[arm].getNrOfJoints(), static_cast<unsigned>(kArmJoints));
      KDL::ChainFkSolverPos_recursive solver(chains[arm]);
      KDL::Frame frame;
      EXPECT_GE(solver.JntToCart(test::UrdfOracle::chain_joints(chains[arm], q_all), frame), 0);
      const Pose tip = chain_tip_pose(*ours[arm], chain_joint_values(*ours[arm], q_all));
      worst = std::max(worst, difference(tip, test::to_pose(frame)));
      worst = std::max(worst, difference(all[ours[arm]->links[ours[arm]->size - 1]], tip));
    }
  }
  return worst;
}

TEST(ForwardKinematics, EveryLinkAndBothPalmChainsMatchKdlBuiltFromTheUrdf) {
  const test::UrdfOracle oracle(test::robot_urdf_text());
  ASSERT_TRUE(oracle.ok());
  EXPECT_EQ(oracle.tree().getNrOfJoints(), static_cast<unsigned>(kJointCount));
  const double worst = worst_difference(oracle, 1, kConfigurations);
  EXPECT_LT(worst, kTolerance) << "worst difference " << worst;
}

TEST(ForwardKinematics, AMutantUrdfMakesTheOracleDisagree) {
  const std::string urdf = test::robot_urdf_text();
  // The elbow axis tilted 20 degrees (what the generator once rounded to -y), and a moved origin.
  const std::string tilted = test::mutate(urdf, "<origin xyz=\"0.0 0.0 -0.3\" rpy=\"0 0 0\"/><axis xyz=\"0 -1 0\"/>",
                                          "<origin xyz=\"0.0 0.0 -0.3\" rpy=\"0 0 0\"/><axis xyz=\"0.34 -0.94 0\"/>");
  const std::string moved = test::mutate(urdf, "<origin xyz=\"0.0 0.0 -0.35\"", "<origin xyz=\"0.0 0.0 -0.36\"");
  for (const std::string* mutant : {&tilted, &moved}) {
    ASSERT_FALSE(mutant->empty()) << "the mutation no longer applies to the URDF";
    const test::UrdfOracle oracle(*mutant);
    ASSERT_TRUE(oracle.ok());
    EXPECT_GT(worst_difference(oracle, 1, 50), 1e-3);
  }
}

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
