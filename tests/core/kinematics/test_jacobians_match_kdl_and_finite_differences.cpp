// Geometric Jacobians: the arm chains' equal KDL's ChainJntToJacSolver to 1e-9 on thousands of
// random configurations; the palms', forearms' and centre of mass's Jacobians over the IK joints
// equal central finite differences of the forward kinematics.
#include <gtest/gtest.h>

#include <kdl/chainjnttojacsolver.hpp>
#include <random>

#include "core/kinematics/centre_of_mass.hpp"
#include "core/kinematics/jacobian.hpp"
#include "tests/core/kinematics/random_configurations.hpp"
#include "tests/core/kinematics/urdf_oracle.hpp"

namespace rescue::kin {
namespace {

constexpr int kConfigurations = 5000;

// Largest difference between our chain Jacobian and KDL's ChainJntToJacSolver on the chain that
// kdl_parser built from the URDF text.
double worst_difference(const std::string& urdf, const Chain& chain, const char* tip, std::uint64_t seed,
                        int configurations) {
  const test::UrdfOracle oracle(urdf);
  EXPECT_TRUE(oracle.ok());
  const KDL::Chain kdl = oracle.chain(tip);
  EXPECT_EQ(kdl.getNrOfJoints(), static_cast<unsigned>(kArmJoints));
  KDL::ChainJntToJacSolver solver(kdl);
  KDL::Jacobian kdl_jacobian(kdl.getNrOfJoints());
  std::mt19937_64 rng(seed);
  double worst = 0.0;
  for (int n = 0; n < configurations; ++n) {
    const JointVector q_all = test::random_configuration(rng);
    EXPECT_GE(solver.JntToJac(test::UrdfOracle::chain_joints(kdl, q_all), kdl_jacobian), 0);
    ArmJacobian j;
    Pose pose;
    chain_jacobian(chain, chain_joint_values(chain, q_all), j, pose);
    worst = std::max(worst, (j - test::to_eigen(kdl_jacobian)).cwiseAbs().maxCoeff());
  }
  return worst;
}

TEST(Jacobian, LeftArmMatchesKdlBuiltFromTheUrdf) {
  const double worst = worst_difference(test::robot_urdf_text(), kLeftArm, "l_ee", 3, kConfigurations);
  EXPECT_LT(worst, 1e-9) << "worst difference " << worst;
}

TEST(Jacobian, RightArmMatchesKdlBuiltFromTheUrdf) {
  const double worst = worst_difference(test::robot_urdf_text(), kRightArm, "r_ee", 4, kConfigurations);
  EXPECT_LT(worst, 1e-9) << "worst difference " << worst;
}

TEST(Jacobian, AMutantUrdfMakesTheOracleDisagree) {
  const std::string tilted = test::mutate(test::robot_urdf_text(), "<axis xyz=\"0 -1 0\"/>", "<axis xyz=\"0.34 -0.94 0\"/>");
  ASSERT_FALSE(tilted.empty());
  EXPECT_GT(worst_difference(tilted, kLeftArm, "l_ee", 3, 50), 1e-3) << "the tilted elbow axis is seen";
}

// Column c of a frame Jacobian by central differences: [dp; w] with [w]x = dR R^T.
IkJacobian6 finite_difference_jacobian(const JointVector& q, std::size_t frame) {
  constexpr double h = 1e-6;
  IkJacobian6 j;
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
    JointVector plus = q;
    JointVector minus = q;
    plus(static_cast<Eigen::Index>(kIkJoints[c])) += h;
    minus(static_cast<Eigen::Index>(kIkJoints[c])) -= h;
    LinkPoses pp;
    LinkPoses pm;
    forward_kinematics(plus, pp);
    forward_kinematics(minus, pm);
    const auto col = static_cast<Eigen::Index>(c);
    j.col(col).head<3>() = (pp[frame].p - pm[frame].p) / (2 * h);
    j.col(col).tail<3>() = rotation_log(pp[frame].R * pm[frame].R.transpose()) / (2 * h);
  }
  return j;
}

TEST(Jacobian, PalmAndForearmJacobiansEqualFiniteDifferences) {
  std::mt19937_64 rng(5);
  for (int n = 0; n < 200; ++n) {
    const JointVector q = test::random_configuration(rng);
    LinkPoses poses;
    forward_kinematics(q, poses);
    for (const std::size_t frame : {kLeftEe, kRightEe, kLeftForearm, kRightForearm}) {
      IkJacobian6 j;
      frame_jacobian(poses, frame, j);
      EXPECT_LT((j - finite_difference_jacobian(q, frame)).cwiseAbs().maxCoeff(), 1e-7) << desc::kLinks[frame].name;
    }
  }
}

TEST(Jacobian, ChainAndWholeRobotJacobiansAgree) {
  std::mt19937_64 rng(6);
  const JointVector q = test::random_configuration(rng);
  LinkPoses poses;
  forward_kinematics(q, poses);
  IkJacobian6 whole;
  frame_jacobian(poses, kRightEe, whole);
  ArmJacobian arm;
  Pose tip;
  chain_jacobian(kRightArm, chain_joint_values(kRightArm, q), arm, tip);
  EXPECT_LT((arm.col(0) - whole.col(0)).cwiseAbs().maxCoeff(), 1e-12);        // waist
  EXPECT_LT((arm.rightCols<6>() - whole.rightCols<6>()).cwiseAbs().maxCoeff(), 1e-12);  // right arm
  EXPECT_TRUE(whole.middleCols<6>(1).isZero(0.0));  // the left arm does not move the right palm
}

TEST(Jacobian, CentreOfMassJacobianEqualsFiniteDifferencesWithPayload) {
  std::mt19937_64 rng(7);
  constexpr double h = 1e-6;
  for (const double payload : {0.0, 70.0}) {
    for (int n = 0; n < 100; ++n) {
      const JointVector q = test::random_configuration(rng);
      LinkPoses poses;
      forward_kinematics(q, poses);
      IkJacobian3 j;
      centre_of_mass_jacobian(poses, payload, j);
      for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
        JointVector plus = q;
        JointVector minus = q;
        plus(static_cast<Eigen::Index>(kIkJoints[c])) += h;
        minus(static_cast<Eigen::Index>(kIkJoints[c])) -= h;
        LinkPoses pp;
        LinkPoses pm;
        forward_kinematics(plus, pp);
        forward_kinematics(minus, pm);
        const Vector3 fd = (centre_of_mass(pp, payload).position - centre_of_mass(pm, payload).position) / (2 * h);
        EXPECT_LT((j.col(static_cast<Eigen::Index>(c)) - fd).cwiseAbs().maxCoeff(), 1e-8) << "column " << c;
      }
    }
  }
}

}  // namespace
}  // namespace rescue::kin
