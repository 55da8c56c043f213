// The URDF (through the generated description) is the robot of core/robot/robot.hpp: every joint of
// kJoints once, with its kind and limits; a half-humanoid on tracks with plausible masses; the
// support polygon under the tracks. (The same agreement is a static_assert in kinematic_model.hpp.)
#include <gtest/gtest.h>

#include <cstring>

#include "core/kinematics/kinematic_model.hpp"

namespace rescue::kin {
namespace {

TEST(UrdfDescription, EveryRobotJointAppearsOnceWithItsLimits) {
  std::array<int, kJointCount> seen{};
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    const desc::Link& link = desc::kLinks[i];
    if (link.type == desc::JointType::fixed) continue;
    const std::size_t j = joint_index_by_name(link.joint);
    ASSERT_LT(j, kJointCount) << link.joint;
    ++seen[j];
    const JointInfo& info = kJoints[j];
    EXPECT_EQ(info.continuous, link.type == desc::JointType::continuous) << link.joint;
    EXPECT_EQ(link.velocity, info.limits.velocity_max_rad_s) << link.joint;
    EXPECT_EQ(link.effort, info.limits.torque_max_nm) << link.joint;
    if (!info.continuous) {
      EXPECT_EQ(link.lower, info.limits.position_min_rad) << link.joint;
      EXPECT_EQ(link.upper, info.limits.position_max_rad) << link.joint;
    }
  }
  for (std::size_t j = 0; j < kJointCount; ++j) EXPECT_EQ(seen[j], 1) << kJoints[j].name;
}

TEST(UrdfDescription, HalfHumanoidOnTracksWithPlausibleMasses) {
  EXPECT_STREQ(desc::kLinks[0].name, "base_link");
  EXPECT_EQ(desc::kLinks[0].parent, -1);
  EXPECT_GT(kRobotMass, 200.0);
  EXPECT_LT(kRobotMass, 400.0);
  for (const desc::Link& link : desc::kLinks) {
    if (std::strcmp(link.name, "l_ee") == 0 || std::strcmp(link.name, "r_ee") == 0) continue;
    EXPECT_GT(link.mass, 0.0) << link.name;
  }
  // Palms hang from wrist pitch links of 7-joint chains that start at the waist.
  EXPECT_STREQ(desc::kLinks[kLeftArm.links[0]].joint, "waist_yaw");
  EXPECT_STREQ(desc::kLinks[kRightArm.links[6]].joint, "r_wrist_pitch");
}

TEST(UrdfDescription, SupportPolygonLiesUnderTheTracks) {
  ASSERT_EQ(desc::kSupportCorners, 4u);
  for (const auto& corner : desc::kSupportPolygon) {
    EXPECT_NEAR(std::fabs(corner[0]), 0.5, 1e-12);  // track length 1 m
    EXPECT_NEAR(std::fabs(corner[1]), 0.43, 1e-12);  // outer edges of the 0.18 m tracks at +-0.34 m
  }
}

}  // namespace
}  // namespace rescue::kin
