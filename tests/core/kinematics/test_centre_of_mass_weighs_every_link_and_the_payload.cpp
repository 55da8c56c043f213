// The centre of mass is the mass-weighted mean of every URDF link's centre of mass plus the
// person held half in each palm, and the support margin says where it stands over the tracks. The
// oracle reads the masses and centres of mass with urdfdom and places the links with the KDL tree
// kdl_parser builds, both from the URDF file (tests/core/kinematics/urdf_oracle.hpp), so it shares
// nothing with the generated description; a URDF with one mass changed makes it disagree.
#include <gtest/gtest.h>

#include <random>

#include "core/kinematics/centre_of_mass.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "tests/core/kinematics/random_configurations.hpp"
#include "tests/core/kinematics/urdf_oracle.hpp"

namespace rescue::kin {
namespace {

// Largest distance between our COM and the oracle's (random configurations, with and without payload).
double worst_difference(const test::UrdfOracle& oracle, int configurations) {
  std::mt19937_64 rng(11);
  double worst = 0.0;
  for (int n = 0; n < configurations; ++n) {
    const JointVector q = test::random_configuration(rng);
    LinkPoses poses;
    forward_kinematics(q, poses);
    for (const double payload : {0.0, 70.0}) {
      worst = std::max(worst, (centre_of_mass(poses, payload).position - oracle.centre_of_mass(q, payload)).norm());
    }
  }
  return worst;
}

TEST(CentreOfMass, EqualsUrdfdomInertialsPlacedByKdlParser) {
  const test::UrdfOracle oracle(test::robot_urdf_text());
  ASSERT_TRUE(oracle.ok());
  EXPECT_NEAR(oracle.mass(), kRobotMass, 1e-12);
  const double worst = worst_difference(oracle, 2500);
  EXPECT_LT(worst, 1e-12) << "worst difference " << worst;
}

TEST(CentreOfMass, AMutantUrdfMakesTheOracleDisagree) {
  const std::string urdf = test::robot_urdf_text();
  // The head (the first 4 kg link) 1 kg heavier; the left upper arm's centre of mass 2 cm lower.
  const std::string heavier = test::mutate(urdf, "<mass value=\"4.0\"/>", "<mass value=\"5.0\"/>");
  const std::string lower = test::mutate(urdf, "<origin xyz=\"0.0 0.0 -0.12\"", "<origin xyz=\"0.0 0.0 -0.14\"");
  for (const std::string* mutant : {&heavier, &lower}) {
    ASSERT_FALSE(mutant->empty()) << "the mutation no longer applies to the URDF";
    const test::UrdfOracle oracle(*mutant);
    ASSERT_TRUE(oracle.ok());
    EXPECT_GT(worst_difference(oracle, 20), 1e-5);
  }
}

TEST(CentreOfMass, AtZeroItIsTheWeightedMeanOfTheUrdfLinks) {
  LinkPoses poses;
  forward_kinematics(JointVector::Zero(), poses);
  // At q = 0 no link is rotated: each link's COM is the sum of origins on its path plus its offset.
  Vector3 moment = Vector3::Zero();
  double mass = 0.0;
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    Vector3 at = Vector3(desc::kLinks[i].com[0], desc::kLinks[i].com[1], desc::kLinks[i].com[2]);
    for (std::size_t k = i; k != 0; k = static_cast<std::size_t>(desc::kLinks[k].parent)) {
      at += Vector3(desc::kLinks[k].origin[0], desc::kLinks[k].origin[1], desc::kLinks[k].origin[2]);
    }
    moment += desc::kLinks[i].mass * at;
    mass += desc::kLinks[i].mass;
  }
  const CentreOfMass com = centre_of_mass(poses, 0.0);
  EXPECT_NEAR(com.mass, mass, 1e-12);
  EXPECT_NEAR(com.mass, kRobotMass, 1e-12);
  EXPECT_LT((com.position - moment / mass).norm(), 1e-12);
  EXPECT_GT(kRobotMass, 200.0) << "a robot that carries a person";
}

TEST(CentreOfMass, PayloadSitsHalfInEachPalm) {
  LinkPoses poses;
  forward_kinematics(ready_posture(), poses);
  const CentreOfMass robot = centre_of_mass(poses, 0.0);
  const CentreOfMass loaded = centre_of_mass(poses, 70.0);
  const Vector3 palms = 0.5 * (poses[kLeftEe].p + poses[kRightEe].p);
  EXPECT_NEAR(loaded.mass, robot.mass + 70.0, 1e-12);
  EXPECT_LT((loaded.position - (robot.mass * robot.position + 70.0 * palms) / loaded.mass).norm(), 1e-12);
  EXPECT_GT(loaded.position.x(), robot.position.x()) << "the person in front moves the COM forward";
}

TEST(CentreOfMass, SupportMarginIsPositiveInsideAndNegativeOutside) {
  const Eigen::Vector2d centre = support_centre();
  EXPECT_GT(support_margin(Vector3(centre.x(), centre.y(), 0.8)), 0.4);
  EXPECT_NEAR(support_margin(Vector3(0.5, 0.0, 0.8)), 0.0, 1e-12);  // on the front edge of the tracks
  EXPECT_LT(support_margin(Vector3(0.7, 0.0, 0.8)), 0.0);
  LinkPoses poses;
  forward_kinematics(ready_posture(), poses);
  EXPECT_GT(support_margin(centre_of_mass(poses, 70.0).position), 0.1);
}

}  // namespace
}  // namespace rescue::kin
