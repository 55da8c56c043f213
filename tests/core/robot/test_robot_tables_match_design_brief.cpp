#include <gtest/gtest.h>

#include <cmath>

#include "core/robot/robot.hpp"

namespace rescue {
namespace {

TEST(Robot, HasTwentyOneJointsOnFourBranches) {
  EXPECT_EQ(kJoints.size(), 21u);
  EXPECT_EQ(__builtin_popcount(joints_of_branch(Branch::torso)), 3);
  EXPECT_EQ(__builtin_popcount(joints_of_branch(Branch::left_arm)), 7);
  EXPECT_EQ(__builtin_popcount(joints_of_branch(Branch::right_arm)), 7);
  EXPECT_EQ(__builtin_popcount(joints_of_branch(Branch::lower_body)), 4);
}

TEST(Robot, FrameOrderFollowsPorts0312) {
  // junction_a, then junction_b (port 3), right arm, lower body, then torso, left arm.
  EXPECT_STREQ(kSlaves[0].name, "junction_a");
  EXPECT_STREQ(kSlaves[1].name, "junction_b");
  EXPECT_STREQ(kSlaves[2].name, "r_shoulder_pitch");
  EXPECT_STREQ(kSlaves[9].name, "l_leg");
  EXPECT_STREQ(kSlaves[13].name, "waist_yaw");
  EXPECT_STREQ(kSlaves[16].name, "l_shoulder_pitch");
  EXPECT_STREQ(kSlaves[22].name, "l_hand");
}

TEST(Robot, LinkFailureLosesJointAndEverythingBehindIt) {
  const std::size_t elbow = joint_index_by_name("l_elbow");
  ASSERT_LT(elbow, kJointCount);
  const JointMask lost = joints_lost_by_link_failure_at(elbow);
  for (const char* name : {"l_elbow", "l_wrist_yaw", "l_wrist_pitch", "l_hand"}) {
    EXPECT_TRUE(lost & joint_bit(joint_index_by_name(name))) << name;
  }
  for (const char* name : {"l_shoulder_pitch", "l_shoulder_roll", "l_shoulder_yaw", "r_hand", "waist_yaw"}) {
    EXPECT_FALSE(lost & joint_bit(joint_index_by_name(name))) << name;
  }
  EXPECT_EQ(joints_lost_by_link_failure_at(joint_index_by_name("waist_yaw")), joints_of_branch(Branch::torso));
}

TEST(Robot, UnknownJointNameIsReported) { EXPECT_EQ(joint_index_by_name("tail"), kJointCount); }

TEST(Robot, JointNameListParsesToAMask) {
  const Result<JointMask> one = parse_joint_names("l_hand");
  ASSERT_TRUE(one.ok());
  EXPECT_EQ(one.value(), joint_bit(joint_index_by_name("l_hand")));
  const Result<JointMask> cut = parse_joint_names("l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand,l_elbow");
  ASSERT_TRUE(cut.ok());
  EXPECT_EQ(cut.value(), joints_lost_by_link_failure_at(joint_index_by_name("l_elbow")));
}

TEST(Robot, JointNameListRejectsUnknownAndEmptyItemsNamingTheItem) {
  const Result<JointMask> unknown = parse_joint_names("l_elbow,tail");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().detail0, 2u);
  EXPECT_STREQ(unknown.error().what, "unknown joint name in the list");
  const Result<JointMask> prefix = parse_joint_names("l_elb");  // no prefix matching
  EXPECT_FALSE(prefix.ok());
  const Result<JointMask> longer = parse_joint_names("l_elbow_and_a_name_longer_than_any_joint_has");
  EXPECT_FALSE(longer.ok());
  const Result<JointMask> empty_item = parse_joint_names("l_elbow,,l_hand");
  ASSERT_FALSE(empty_item.ok());
  EXPECT_EQ(empty_item.error().detail0, 2u);
  EXPECT_FALSE(parse_joint_names("").ok());
  EXPECT_FALSE(parse_joint_names("l_hand,").ok());
  EXPECT_FALSE(parse_joint_names(nullptr).ok());
}

}  // namespace
}  // namespace rescue
