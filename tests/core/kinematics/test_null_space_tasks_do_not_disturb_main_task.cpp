// The sub-tasks (forearms level, COM over the tracks) act in the main task's null space: with or
// without them, a step moves both palms the same way (to first order, J1 dq); and they do work:
// holding the palms still, repeated steps level the forearms and move the COM towards the centre.
#include <gtest/gtest.h>

#include <random>

#include "core/kinematics/jacobian.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/kinematics/task_priority_ik.hpp"

namespace rescue::kin {
namespace {

Eigen::Matrix<double, 12, kIkDof> palm_jacobian(const JointVector& q) {
  LinkPoses poses;
  forward_kinematics(q, poses);
  Eigen::Matrix<double, 12, kIkDof> j;
  IkJacobian6 part;
  frame_jacobian(poses, kLeftEe, part);
  j.topRows<6>() = part;
  frame_jacobian(poses, kRightEe, part);
  j.bottomRows<6>() = part;
  return j;
}

IkVector ik_part(const JointVector& dq) {
  IkVector out;
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) out(static_cast<Eigen::Index>(c)) = dq(static_cast<Eigen::Index>(kIkJoints[c]));
  return out;
}

TEST(NullSpace, SubTasksDoNotChangeThePalmMotion) {
  std::mt19937_64 rng(21);
  std::normal_distribution<double> noise(0.0, 0.2);
  IkSettings with;
  IkSettings without = with;
  without.forearm_task = false;
  without.com_task = false;
  for (int n = 0; n < 100; ++n) {
    JointVector q = ready_posture();
    for (const std::size_t j : kIkJoints) q(static_cast<Eigen::Index>(j)) += noise(rng);
    LinkPoses poses;
    forward_kinematics(q, poses);
    IkTargets targets{poses[kLeftEe], poses[kRightEe], 70.0};
    targets.left.p += Vector3(0.002, -0.001, 0.001);
    targets.right.p += Vector3(0.001, 0.002, -0.002);
    TaskPriorityIk ik_with(with);
    TaskPriorityIk ik_without(without);
    JointVector next_with;
    JointVector next_without;
    const Result<IkStepReport> a = ik_with.step(q, targets, 0, next_with);
    const Result<IkStepReport> b = ik_without.step(q, targets, 0, next_without);
    ASSERT_TRUE(a.ok() && b.ok());
    if (a.value().velocity_scale < 1.0 || b.value().velocity_scale < 1.0 || a.value().at_limit != 0 ||
        a.value().sigma_min < with.singular_threshold) {
      continue;  // limited or damped steps are not pure null-space comparisons
    }
    const auto j = palm_jacobian(q);
    const auto palms_with = j * ik_part(next_with - q);
    const auto palms_without = j * ik_part(next_without - q);
    EXPECT_LT((palms_with - palms_without).cwiseAbs().maxCoeff(), 1e-8) << "configuration " << n;
    EXPECT_GT((next_with - next_without).cwiseAbs().maxCoeff(), 1e-7) << "the sub-tasks moved something";
  }
}

TEST(NullSpace, SubTasksLevelTheForearmsWhileThePalmsHold) {
  JointVector q = ready_posture();
  q(static_cast<Eigen::Index>(joint_index("l_shoulder_pitch"))) = -0.3;  // forearms tilted
  q(static_cast<Eigen::Index>(joint_index("r_shoulder_pitch"))) = -0.3;
  LinkPoses poses;
  forward_kinematics(q, poses);
  const IkTargets targets{poses[kLeftEe], poses[kRightEe], 0.0};
  TaskPriorityIk ik;
  JointVector next;
  Result<IkStepReport> first = ik.step(q, targets, 0, next);
  ASSERT_TRUE(first.ok());
  const double tilt_before = std::fabs(first.value().forearm_tilt[0]) + std::fabs(first.value().forearm_tilt[1]);
  IkStepReport last = first.value();
  for (int k = 0; k < 5000; ++k) {
    q = next;
    const Result<IkStepReport> r = ik.step(q, targets, 0, next);
    ASSERT_TRUE(r.ok());
    last = r.value();
  }
  const double tilt_after = std::fabs(last.forearm_tilt[0]) + std::fabs(last.forearm_tilt[1]);
  EXPECT_LT(tilt_after, tilt_before) << "before " << tilt_before << " after " << tilt_after;
  EXPECT_LT(std::max(last.position_residual_m[0], last.position_residual_m[1]), 1e-5);
  EXPECT_LT(std::max(last.rotation_residual_rad[0], last.rotation_residual_rad[1]), 1e-4);
}

}  // namespace
}  // namespace rescue::kin
