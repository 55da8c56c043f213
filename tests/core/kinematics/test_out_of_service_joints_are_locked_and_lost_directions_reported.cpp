// Joints out of service (lost after damage, in Error) are held at their positions and left out of
// the solution; the remaining joints still do what they can, and the lost capability names the
// task directions of each palm the remaining joints can no longer move.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <cstring>

#include "core/kinematics/jacobian.hpp"
#include "core/kinematics/lost_capability.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/kinematics/task_priority_ik.hpp"

namespace rescue::kin {
namespace {

JointMask mask_of(std::initializer_list<const char*> names) {
  JointMask mask = 0;
  for (const char* name : names) mask |= joint_bit(joint_index(name));
  return mask;
}

TEST(OutOfService, LockedJointsHoldAndTheOtherArmStillReachesItsTarget) {
  JointVector q = ready_posture();
  LinkPoses poses;
  forward_kinematics(q, poses);
  IkTargets targets{poses[kLeftEe], poses[kRightEe], 0.0};
  targets.left.p += Vector3(0.05, 0.0, -0.05);
  targets.right.p += Vector3(0.05, 0.0, -0.05);
  const JointMask lost = joints_lost_by_link_failure_at(joint_index("l_elbow"));  // elbow, wrist, hand
  const JointVector start = q;
  TaskPriorityIk ik;
  const Result<IkStepReport> r = ik.solve(q, targets, lost, 5000, 1e-5, 1e-4);
  ASSERT_TRUE(r.ok());
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((lost & joint_bit(j)) != 0) {
      EXPECT_EQ(q(static_cast<Eigen::Index>(j)), start(static_cast<Eigen::Index>(j))) << kJoints[j].name;
    }
  }
  EXPECT_LT(r.value().position_residual_m[1], 1e-4) << "the right arm does its task";
  EXPECT_GT(r.value().position_residual_m[0] + r.value().rotation_residual_rad[0], 1e-3)
      << "the left palm cannot reach a pose that needs its elbow";
}

TEST(OutOfService, HealthyRobotLosesNoDirection) {
  const LostCapability cap = analyse_lost_capability(ready_posture(), 0);
  for (const ArmCapability& arm : cap.arms) {
    EXPECT_EQ(arm.lost_directions, 0);
    EXPECT_EQ(arm.uncontrollable_axes, 0);
    EXPECT_GT(arm.sigma_min, 0.05);
  }
}

// The lost directions are those the remaining columns cannot produce: J_reduced^T d = 0.
void expect_unreachable_directions(const ArmCapability& arm, std::size_t frame, JointMask lost) {
  LinkPoses poses;
  forward_kinematics(ready_posture(), poses);
  IkJacobian6 j;
  frame_jacobian(poses, frame, j);
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
    if ((lost & joint_bit(kIkJoints[c])) != 0) j.col(static_cast<Eigen::Index>(c)).setZero();
  }
  for (int k = 0; k < arm.lost_directions; ++k) {
    const Vector6 d = arm.directions.col(k);
    EXPECT_NEAR(d.norm(), 1.0, 1e-12);
    EXPECT_LT((j.transpose() * d).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(OutOfService, OneLostJointIsCoveredByTheSevenJointArmsRedundancy) {
  // Each palm has 7 joints (waist + 6): losing one of them leaves 6, still every direction.
  const LostCapability cap = analyse_lost_capability(ready_posture(), mask_of({"l_elbow"}));
  EXPECT_EQ(cap.arms[0].lost_directions, 0);
  EXPECT_EQ(cap.arms[1].lost_directions, 0);
}

TEST(OutOfService, ALockedElbowFixesTheWristDistanceAndTheReachItCosts) {
  // Elbow locked at pi/2 (the ready posture): the palm keeps its six directions there, but the
  // distance from the shoulder yaw joint to the wrist is fixed at sqrt(0.30^2 + 0.35^2).
  const JointMask lost = mask_of({"l_elbow"});
  const LostCapability cap = analyse_lost_capability(ready_posture(), lost);
  EXPECT_EQ(cap.arms[0].lost_directions, 0);
  EXPECT_TRUE(cap.arms[0].reach_fixed);
  EXPECT_FALSE(cap.arms[1].reach_fixed);
  EXPECT_NEAR(cap.arms[0].wrist_distance_m, std::sqrt(0.30 * 0.30 + 0.35 * 0.35), 1e-12);
  EXPECT_NEAR(cap.arms[0].wrist_distance_max_m, 0.65, 1e-12);  // elbow straight
  EXPECT_NEAR(cap.arms[0].wrist_distance_min_m,
              std::sqrt(0.30 * 0.30 + 0.35 * 0.35 + 2 * 0.30 * 0.35 * std::cos(2.5)), 1e-12);  // elbow at 2.5 rad
  // A target the fixed distance cannot reach (the palm 0.2 m further forward, the arm would have
  // to stretch) leaves a residual although no direction is lost; with its elbow the arm reaches it.
  JointVector q = ready_posture();
  LinkPoses poses;
  forward_kinematics(q, poses);
  IkTargets targets{poses[kLeftEe], poses[kRightEe], 0.0};
  targets.left.p += Vector3(0.2, 0.0, 0.0);
  targets.right.p += Vector3(0.2, 0.0, 0.0);
  TaskPriorityIk ik;
  const Result<IkStepReport> r = ik.solve(q, targets, lost, 6000, 1e-6, 1e-5);
  ASSERT_TRUE(r.ok());
  std::printf("locked elbow: left residual %.4f m %.4f rad, right residual %.2e m\n", r.value().position_residual_m[0],
              r.value().rotation_residual_rad[0], r.value().position_residual_m[1]);
  EXPECT_GT(r.value().position_residual_m[0] + r.value().rotation_residual_rad[0], 0.01);
  // The waist, shared, is pulled towards the unreachable left target; the left palm, further from its
  // target, is damped more, so the right palm pays little (measured 0.31 mm; 3.1 mm before the share).
  EXPECT_LT(r.value().position_residual_m[1], 0.005);
  const JointVector healthy_start = ready_posture();
  JointVector healthy = healthy_start;
  TaskPriorityIk healthy_ik;
  const Result<IkStepReport> h = healthy_ik.solve(healthy, targets, 0, 6000, 1e-6, 1e-5);
  ASSERT_TRUE(h.ok());
  EXPECT_LT(h.value().position_residual_m[0], 1e-4) << "with its elbow the arm reaches it";
}

TEST(OutOfService, LostElbowAndWaistCostTheLeftPalmOneDirection) {
  const JointMask lost = mask_of({"l_elbow", "waist_yaw"});
  const LostCapability cap = analyse_lost_capability(ready_posture(), lost);
  EXPECT_EQ(cap.arms[0].lost_directions, 1);
  EXPECT_EQ(cap.arms[1].lost_directions, 0);
  expect_unreachable_directions(cap.arms[0], kLeftEe, lost);
}

TEST(OutOfService, LostWristJointsCostTheRightPalmTwoDirectionsInTheReadyPosture) {
  // Five columns remain, but in the ready posture the shoulder yaw is parallel to the waist and
  // the shoulder pitch to the elbow: rank 4, two directions lost.
  const JointMask lost = mask_of({"r_wrist_yaw", "r_wrist_pitch"});
  const LostCapability cap = analyse_lost_capability(ready_posture(), lost);
  EXPECT_EQ(cap.arms[0].lost_directions, 0);
  EXPECT_EQ(cap.arms[1].lost_directions, 2);
  EXPECT_NE(cap.arms[1].uncontrollable_axes, 0);
  expect_unreachable_directions(cap.arms[1], kRightEe, lost);
}

TEST(OutOfService, LostWaistIsCoveredByEachArmsOwnSixJoints) {
  const LostCapability cap = analyse_lost_capability(ready_posture(), mask_of({"waist_yaw"}));
  EXPECT_EQ(cap.arms[0].lost_directions, 0);
  EXPECT_EQ(cap.arms[1].lost_directions, 0);
}

TEST(OutOfService, WholeArmLostLosesEveryDirectionOfItsPalm) {
  const LostCapability cap = analyse_lost_capability(
      ready_posture(), joints_lost_by_link_failure_at(joint_index("l_shoulder_pitch")) | mask_of({"waist_yaw"}));
  EXPECT_EQ(cap.arms[0].lost_directions, 6);
  EXPECT_EQ(cap.arms[0].uncontrollable_axes, 0x3F);
  char axes[32];
  format_axes(cap.arms[0].uncontrollable_axes, axes, sizeof axes);
  EXPECT_STREQ(axes, "x,y,z,rx,ry,rz");
  format_axes(0, axes, sizeof axes);
  EXPECT_STREQ(axes, "none");
}

}  // namespace
}  // namespace rescue::kin
