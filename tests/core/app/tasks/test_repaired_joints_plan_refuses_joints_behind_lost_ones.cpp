// The operator's --clear-joint request judged against the joints the error-joints file restored.
#include <gtest/gtest.h>

#include "core/app/tasks/repaired_joints.hpp"

namespace rescue::app {
namespace {

JointMask joint(const char* name) { return joint_bit(joint_index_by_name(name)); }

const JointMask kElbowCut = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));

TEST(RepairedJointsPlan, ClearingTheWholeCutLeavesNothingOutOfService) {
  const RepairedJointsPlan plan = plan_repaired_joints(kElbowCut, kElbowCut);
  EXPECT_FALSE(plan.refused());
  EXPECT_EQ(plan.to_clear, kElbowCut);
  EXPECT_EQ(plan.out_of_service, JointMask{0});
  EXPECT_EQ(plan.not_recorded, JointMask{0});
}

TEST(RepairedJointsPlan, ClearingOnlyTheFirstJointKeepsTheOnesBehindItLost) {
  const RepairedJointsPlan plan = plan_repaired_joints(joint("l_elbow"), kElbowCut);
  EXPECT_FALSE(plan.refused());
  EXPECT_EQ(plan.to_clear, joint("l_elbow"));
  EXPECT_EQ(plan.out_of_service, kElbowCut & ~joint("l_elbow"));
}

TEST(RepairedJointsPlan, AJointBehindOneThatStaysLostRefusesTheRequest) {
  const RepairedJointsPlan plan = plan_repaired_joints(joint("l_elbow") | joint("l_hand"), kElbowCut);
  EXPECT_TRUE(plan.refused());
  EXPECT_EQ(plan.stranded, joint("l_hand"));
  EXPECT_EQ(plan.blocking, joint("l_wrist_yaw") | joint("l_wrist_pitch"));
}

TEST(RepairedJointsPlan, JointsNotRecordedLostAreReportedAndIgnored) {
  const RepairedJointsPlan plan = plan_repaired_joints(joint("neck_pan") | joint("l_elbow"), kElbowCut);
  EXPECT_FALSE(plan.refused());
  EXPECT_EQ(plan.not_recorded, joint("neck_pan"));
  EXPECT_EQ(plan.to_clear, joint("l_elbow"));
}

TEST(RepairedJointsPlan, JointsOnOtherBranchesDoNotBlockEachOther) {
  const JointMask right_hand = joint("r_hand");
  const RepairedJointsPlan plan = plan_repaired_joints(right_hand, kElbowCut | right_hand);
  EXPECT_FALSE(plan.refused());
  EXPECT_EQ(plan.to_clear, right_hand);
  EXPECT_EQ(plan.out_of_service, kElbowCut);
}

}  // namespace
}  // namespace rescue::app
