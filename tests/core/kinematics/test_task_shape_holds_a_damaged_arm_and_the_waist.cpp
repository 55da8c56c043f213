// The task stack after damage (kin::TaskShape): a joint lost in an arm takes that palm out of the
// main task and holds the arm's other IK joints and the waist; joints outside the arms' IK joints
// change nothing; the IK then moves no held joint and tracks the healthy palm with its own arm.
#include <gtest/gtest.h>

#include "core/kinematics/rescue_motion.hpp"
#include "core/kinematics/task_priority_ik.hpp"
#include "core/kinematics/task_shape.hpp"

namespace rescue::kin {
namespace {

JointMask bit(const char* name) { return joint_bit(joint_index(name)); }

TEST(TaskShape, NoJointOutOfServiceKeepsBothPalmsAndHoldsNothing) {
  const TaskShape shape = task_shape_for(0);
  EXPECT_TRUE(shape.palm_active[0]);
  EXPECT_TRUE(shape.palm_active[1]);
  EXPECT_EQ(shape.held, 0U);
}

TEST(TaskShape, ALostElbowDropsThatPalmAndHoldsTheShoulderAndTheWaist) {
  const JointMask lost = joints_lost_by_link_failure_at(joint_index("l_elbow"));
  const TaskShape shape = task_shape_for(lost);
  EXPECT_FALSE(shape.palm_active[0]);
  EXPECT_TRUE(shape.palm_active[1]);
  EXPECT_EQ(shape.held, bit("l_shoulder_pitch") | bit("l_shoulder_roll") | bit("l_shoulder_yaw") | bit("waist_yaw"));
}

TEST(TaskShape, JointsOutsideTheArmsIkChangeNothing) {
  for (const char* name : {"l_hand", "r_hand", "neck_pan", "l_leg", "r_track"}) {
    const TaskShape shape = task_shape_for(bit(name));
    EXPECT_TRUE(shape.palm_active[0] && shape.palm_active[1]) << name;
    EXPECT_EQ(shape.held, 0U) << name;
  }
}

TEST(TaskShape, ALostWaistKeepsBothPalmsOnTheirArms) {
  const TaskShape shape = task_shape_for(bit("waist_yaw"));
  EXPECT_TRUE(shape.palm_active[0] && shape.palm_active[1]);
  EXPECT_EQ(shape.held, 0U);
}

TEST(TaskShape, BothArmsDamagedHoldEveryIkJointInService) {
  const JointMask lost = bit("l_wrist_pitch") | bit("r_shoulder_pitch");
  const TaskShape shape = task_shape_for(lost);
  EXPECT_FALSE(shape.palm_active[0] || shape.palm_active[1]);
  JointMask ik = 0;
  for (const std::size_t j : kIkJoints) ik |= joint_bit(j);
  EXPECT_EQ(shape.held, ik & ~lost);
}

TEST(TaskShape, TheIkWithTheLeftPalmDroppedMovesOnlyTheRightArmTowardsItsTarget) {
  const JointVector q = ready_posture();
  LinkPoses poses;
  forward_kinematics(q, poses);
  IkTargets targets{poses[kLeftEe], poses[kRightEe]};
  targets.left.p.z() -= 0.2;   // unreachable for the damaged arm: must be ignored
  targets.right.p.x() += 0.02;
  const JointMask lost = joints_lost_by_link_failure_at(joint_index("l_elbow"));
  const TaskShape shape = task_shape_for(lost);
  targets.palm_active = shape.palm_active;
  TaskPriorityIk ik;
  JointVector next = q;
  const Result<IkStepReport> r = ik.step(q, targets, lost | shape.held, next);
  ASSERT_TRUE(r.ok());
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((arm_ik_joints(1) & joint_bit(j)) != 0) continue;
    EXPECT_EQ(next(static_cast<Eigen::Index>(j)), q(static_cast<Eigen::Index>(j))) << kJoints[j].name;
  }
  forward_kinematics(next, poses);
  EXPECT_GT(poses[kRightEe].p.x(), targets.right.p.x() - 0.02 + 1e-4) << "the right palm moved towards its target";
  EXPECT_GT(r.value().sigma_min, 0.08) << "a dropped palm is no singularity (no extra damping)";
}

}  // namespace
}  // namespace rescue::kin
