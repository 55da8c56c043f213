// The centre of mass is the mass-weighted mean of every URDF link's centre of mass plus the
// person held half in each palm, and the support margin says where it stands over the tracks.
#include <gtest/gtest.h>

#include "core/kinematics/centre_of_mass.hpp"
#include "core/kinematics/rescue_motion.hpp"

namespace rescue::kin {
namespace {

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
