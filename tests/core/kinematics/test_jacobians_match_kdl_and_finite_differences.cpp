// Geometric Jacobians: the arm chains' equal KDL's ChainJntToJacSolver to 1e-9 on thousands of
// random configurations; the palms', forearms' and centre of mass's Jacobians over the IK joints
// equal central finite differences of the forward kinematics.
#include <gtest/gtest.h>

#include <kdl/chainjnttojacsolver.hpp>
#include <random>

#include "core/kinematics/centre_of_mass.hpp"
#include "core/kinematics/jacobian.hpp"
#include "tests/core/kinematics/kdl_chain.hpp"
#include "tests/core/kinematics/random_configurations.hpp"

namespace rescue::kin {
namespace {

constexpr int kConfigurations = 5000;

void expect_chain_jacobian_matches_kdl(const Chain& chain, std::uint64_t seed) {
  const KDL::Chain kdl = test::make_kdl_chain(chain);
  KDL::ChainJntToJacSolver solver(kdl);
  KDL::Jacobian kdl_jacobian(kdl.getNrOfJoints());
  std::mt19937_64 rng(seed);
  double worst = 0.0;
  for (int n = 0; n < kConfigurations; ++n) {
    const ArmVector q = chain_joint_values(chain, test::random_configuration(rng));
    ASSERT_GE(solver.JntToJac(test::to_kdl(q), kdl_jacobian), 0);
    ArmJacobian j;
    Pose tip;
    chain_jacobian(chain, q, j, tip);
    worst = std::max(worst, (j - test::to_eigen(kdl_jacobian)).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-9) << "worst difference " << worst;
}

TEST(Jacobian, LeftArmMatchesKdlOnRandomConfigurations) { expect_chain_jacobian_matches_kdl(kLeftArm, 3); }

TEST(Jacobian, RightArmMatchesKdlOnRandomConfigurations) { expect_chain_jacobian_matches_kdl(kRightArm, 4); }

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
