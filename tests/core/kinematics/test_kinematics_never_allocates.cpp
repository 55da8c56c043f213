// No heap on the RC path: whole RC periods (rescue motion, IK, teleop), a link cut that triggers
// the lost-capability analysis, IK steps with the self-collision sub-task's pairs close, and every kernel bench rc measures, run with Eigen's run-time
// allocation check (EIGEN_RUNTIME_NO_MALLOC, set_is_malloc_allowed(false)) and the heap guard in
// strict mode: any allocation would abort the test.
#include <gtest/gtest.h>

#include "core/memory/heap_guard.hpp"
#include "core/kinematics/centre_of_mass.hpp"
#include "core/kinematics/damped_least_squares.hpp"
#include "core/kinematics/rc_period.hpp"

namespace rescue::kin {
namespace {

TEST(NoHeap, RcPeriodsAndKernelsNeverAllocate) {
  RcPeriod rc(ready_posture());
  JointVector teleop_velocity = JointVector::Zero();
  teleop_velocity(static_cast<Eigen::Index>(joint_index("neck_pan"))) = 0.3;
  const JointMask cut = joints_lost_by_link_failure_at(joint_index("r_wrist_yaw"));
  LinkPoses poses;
  ArmJacobian arm_jacobian;
  IkJacobian6 frame_j;
  IkJacobian3 com_j;
  ArmVector qdot;
  Pose tip;
  int failures = 0;
  double checksum = 0.0;

  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 3000; ++k) {
    const Result<IkStepReport> r = rc.run(k * 0.003, k >= 1500 ? cut : 0, teleop_velocity);
    if (!r.ok()) ++failures;
    const JointVector& q = rc.rescue_references();
    forward_kinematics(q, poses);
    frame_jacobian(poses, kLeftForearm, frame_j);
    centre_of_mass_jacobian(poses, 70.0, com_j);
    const ArmVector qa = chain_joint_values(kLeftArm, q);
    chain_jacobian(kLeftArm, qa, arm_jacobian, tip);
    (void)arm_velocity_ik(kLeftArm, qa, Vector6::Constant(0.01), qdot);
    checksum += chain_tip_pose(kRightArm, chain_joint_values(kRightArm, q)).p.x() + qdot(0) + com_j(0, 0);
  }
  // The self-collision sub-task with pairs close: the waist turned towards the tracks' envelopes,
  // the tracks turning.
  TaskPriorityIk ik;
  JointVector q_close = ready_posture();
  q_close(static_cast<Eigen::Index>(joint_index("waist_yaw"))) = 0.14;
  JointVector q_next = q_close;
  forward_kinematics(q_close, poses);
  const IkTargets hold{poses[kLeftEe], poses[kRightEe]};
  int close_steps = 0;
  for (int k = 0; k < 500; ++k) {
    q_close(static_cast<Eigen::Index>(joint_index("l_track"))) = 0.01 * k;
    const Result<IkStepReport> r = ik.step(q_close, hold, 0, q_next);
    if (!r.ok()) ++failures;
    if (r.ok() && r.value().self_collision.close_pairs > 0) ++close_steps;
    q_close = q_next;
  }
  Eigen::internal::set_is_malloc_allowed(true);
  const HeapGuardCounters counters = heap_guard_counters();
  reopen_init_for_testing();

  EXPECT_EQ(counters.allocations, 0u);
  EXPECT_EQ(counters.bytes, 0u);
  EXPECT_EQ(failures, 0);
  EXPECT_TRUE(std::isfinite(checksum));
  EXPECT_EQ(rc.out_of_service(), cut);
  EXPECT_GT(close_steps, 100);
}

#ifndef NDEBUG
// The check is live: a dynamic-size Eigen matrix under set_is_malloc_allowed(false) aborts.
TEST(NoHeapDeathTest, EigenRuntimeCheckCatchesADynamicMatrix) {
  EXPECT_DEATH(
      {
        Eigen::internal::set_is_malloc_allowed(false);
        Eigen::MatrixXd m(20, 20);
        m.setZero();
      },
      "is_malloc_allowed");
}
#endif

}  // namespace
}  // namespace rescue::kin
