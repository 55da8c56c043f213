// The two RC tasks (core/app/tasks/rescue_task.hpp, teleop_task.hpp) with the handler's motion intake, in
// virtual time (tests/support/rc_task_rig.hpp):
//   both compute every period; only the owner's references reach the joints;
//   the rescue task's motion goes through approach, lowering, forwarding, backwarding to done,
//   and goes on with the healthy arm after a link cut (the lost joints never commanded, the damaged
//   arm's other joints braked to rest and held);
//   an owner that dies is released within kOwnerDeadAfterPeriods + 1 periods, the joints hold,
//   the teleop task takes over bumplessly, and a restarted rescue task waits for the operator;
//   a restarted owner's process frees its predecessor's word if it beats before the handler noticed;
//   an owner that stalls and comes back takes the free motion back.
#include <gtest/gtest.h>

#include <cmath>

#include "core/app/config/firmware_config.hpp"
#include "tests/support/rc_task_rig.hpp"

namespace rescue::app {
namespace {

const std::size_t kLeftElbow = joint_index_by_name("l_elbow");
const std::size_t kRightElbow = joint_index_by_name("r_elbow");
const std::size_t kLeftShoulder = joint_index_by_name("l_shoulder_pitch");
const std::size_t kLeftHand = joint_index_by_name("l_hand");

TEST(RcTasks, TheRescueTaskOwnsItsMotionToTheEndWhileTeleopComputesWithoutDriving) {
  testing::RcTaskRig rig;
  rig.steps(5);
  EXPECT_EQ(rig.links->motion.owner.task(), kNoOwnerTask);
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  // The operator closes the left hand through the teleop task, which does not own the motion.
  ASSERT_TRUE(rig.send(RcTaskId::teleop, RcInputKind::hand, 0, static_cast<std::uint8_t>(protocol::HandAction::close)));
  rig.step();
  EXPECT_EQ(rig.links->motion.owner.task(), 0);
  EXPECT_EQ(rig.rescue->mode(), RcMode::approach);
  int steps = 0;
  // The rig's phases (0.4 s each) ask for more than the arms' acceleration limits: the motion slows
  // down to keep its path (kin::RcPeriod's time scaling) and takes longer than 1.2 s.
  while (rig.rescue->rescue_phase() != kin::RescuePhase::done && steps < 20000) {
    rig.step();
    ++steps;
  }
  EXPECT_EQ(rig.rescue->rescue_phase(), kin::RescuePhase::done);
  EXPECT_EQ(rig.rescue->counters().periods, rig.teleop->counters().periods) << "both compute every period";
  EXPECT_EQ(rig.intake.counters().misses, 0U);
  EXPECT_EQ(rig.intake.driving_task(), 0);
  EXPECT_EQ(rig.rescue->counters().kinematics_errors, 0U);
  // The joints follow the rescue task's references (the elbows went from hanging to bent).
  EXPECT_GT(rig.sent[kRightElbow], 1.0);
  EXPECT_NEAR(rig.sent[kRightElbow], rig.rescue->references()(static_cast<Eigen::Index>(kRightElbow)), 1e-9);
  // The teleop task closed its left hand in its own reference space; that never reached the joint.
  EXPECT_GT(rig.teleop->references()(static_cast<Eigen::Index>(kLeftHand)), 0.5);
  EXPECT_DOUBLE_EQ(rig.sent[kLeftHand], 0.0);
  ReferenceSnapshot teleop_space;
  ASSERT_TRUE(rig.links->motion.references[1].read(teleop_space));
  EXPECT_EQ(teleop_space.owner_word, 0U) << "written, but not as the owner";
}

TEST(RcTasks, TheRescueMotionGoesOnWithTheRemainingJointsAfterALinkCut) {
  testing::RcTaskRig rig;
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  rig.steps(1600);  // approach, then into forwarding
  for (int k = 0; k < 20000 && rig.rescue->rescue_phase() != kin::RescuePhase::forwarding; ++k) rig.step();
  rig.steps(100);
  ASSERT_EQ(rig.rescue->rescue_phase(), kin::RescuePhase::forwarding);
  rig.cut_link_at(kLeftElbow);
  const std::array<double, kJointCount> at_cut = rig.sent;
  const double shoulder_at_cut = rig.sent[kLeftShoulder];
  rig.steps(2);
  ReferenceSnapshot space;
  ASSERT_TRUE(rig.links->motion.references[0].read(space));
  EXPECT_EQ(space.commanded & rig.unreachable, 0U) << "joints out of service are never commanded";
  EXPECT_EQ(rig.rescue->out_of_service(), rig.unreachable);
  while (rig.rescue->rescue_phase() != kin::RescuePhase::done && rig.rescue->counters().periods < 30000) rig.step();
  EXPECT_EQ(rig.rescue->rescue_phase(), kin::RescuePhase::done);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((rig.unreachable & joint_bit(j)) != 0) {
      EXPECT_DOUBLE_EQ(rig.sent[j], at_cut[j]) << kJoints[j].name;
    }
  }
  // The damaged arm's remaining joints brake to rest and hold (kin::TaskShape): they never drag the
  // unpowered forearm; a joint moving at v stops within v^2 / 2a.
  const double a = kin::kJointAcceleration[kLeftShoulder];
  EXPECT_LE(std::fabs(rig.sent[kLeftShoulder] - shoulder_at_cut),
            kJoints[kLeftShoulder].limits.velocity_max_rad_s * kJoints[kLeftShoulder].limits.velocity_max_rad_s / (2 * a));
  EXPECT_EQ(rig.rescue->references()(static_cast<Eigen::Index>(kin::joint_index("waist_yaw"))),
            rig.sent[kin::joint_index("waist_yaw")]);
  EXPECT_EQ(rig.intake.counters().misses, 0U);
  EXPECT_EQ(rig.rescue->counters().kinematics_errors, 0U);
}

TEST(RcTasks, ADeadOwnerIsReleasedTheJointsHoldAndTeleopTakesOverBumplessly) {
  testing::RcTaskRig rig;
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  rig.steps(400);  // in the approach: the joints are moving
  std::array<double, kJointCount> previous = rig.sent;
  std::array<double, kJointCount> step{};  // each joint's reference step last period
  rig.step();
  for (std::size_t j = 0; j < kJointCount; ++j) step[j] = rig.sent[j] - previous[j];
  previous = rig.sent;
  rig.rescue_runs = false;  // the rescue task dies (its process is killed)
  int periods = 0;
  while (rig.links->motion.owner.task() == 0 && periods < 1000) {
    rig.step();
    ++periods;
    // From the first missed period on, each joint comes to rest within its deceleration limit: its
    // reference's step shrinks by at most a * dt^2 a period and never reverses (docs/motion-owner.md).
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const double now_step = rig.sent[j] - previous[j];
      const double a = deceleration_limit_rad_s2(kJoints[j].limits);
      EXPECT_LE(std::fabs(now_step), std::fabs(step[j]) + 1e-12) << kJoints[j].name << ": never faster";
      EXPECT_LE(std::fabs(step[j]) - std::fabs(now_step), a * 1e-6 + 1e-12) << kJoints[j].name << ": within its deceleration";
      EXPECT_GE(now_step * step[j], 0.0) << kJoints[j].name << ": never backwards";
      step[j] = now_step;
    }
    previous = rig.sent;
  }
  EXPECT_EQ(rig.links->motion.owner.task(), kNoOwnerTask);
  EXPECT_LE(periods, config::kOwnerDeadAfterPeriods + 1);
  EXPECT_EQ(rig.intake.counters().releases, 1U);
  rig.steps(300);  // at rest within kStopFromVelocityLimitS (core/robot/robot.hpp)
  const std::array<double, kJointCount> before = rig.sent;
  rig.step();
  EXPECT_EQ(rig.sent, before) << "then the joints hold";
  // The operator hands the motion to teleop: it continues from the references being sent.
  ASSERT_TRUE(rig.send(RcTaskId::teleop, RcInputKind::take_ownership));
  rig.step();
  EXPECT_EQ(rig.links->motion.owner.task(), 1);
  rig.step();
  EXPECT_EQ(rig.intake.driving_task(), 1);
  for (std::size_t j = 0; j < kJointCount; ++j) EXPECT_NEAR(rig.sent[j], before[j], 1e-12) << kJoints[j].name;
  // The rescue task restarted (a new process): it computes, but waits for the operator.
  rig.rescue = std::make_unique<RescueTask>(rig.ports->rc_task(RcTaskId::rescue), testing::short_rescue_settings());
  rig.rescue_runs = true;
  rig.steps(10);
  EXPECT_EQ(rig.links->motion.owner.task(), 1);
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  rig.steps(10);
  EXPECT_EQ(rig.links->motion.owner.task(), 0);
  EXPECT_EQ(rig.intake.driving_task(), 0);
  EXPECT_EQ(rig.teleop->counters().ownership_lost, 1U);
}

// The supervisor restarts a killed owner's process; if the new process beats before the handler
// noticed the death (the handler held off its CPU longer than the back-off), its fresh heartbeat
// makes the dead generation's word look alive to the handler. Before this rule the new process
// adopted that word (owning without the operator's choice: a restarted teleop task would drive the
// joints) and the handler never released it. Now it frees its predecessor's word in its first
// period, as the intake would have: the joints hold and the operator gives the motion again.
TEST(RcTasks, ARestartedTaskThatBeatsBeforeTheReleaseFreesItsPredecessorsWord) {
  testing::RcTaskRig rig;
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  rig.steps(400);
  rig.rescue_runs = false;  // killed
  rig.steps(10);            // the handler brings its joints to rest; not yet released
  ASSERT_EQ(rig.links->motion.owner.task(), 0);
  rig.rescue = std::make_unique<RescueTask>(rig.ports->rc_task(RcTaskId::rescue), testing::short_rescue_settings());
  rig.rescue_runs = true;
  rig.step();
  EXPECT_EQ(rig.links->motion.owner.task(), kNoOwnerTask) << "the predecessor's word is freed at once";
  EXPECT_EQ(rig.rescue->counters().predecessor_releases, 1U);
  const std::uint64_t misses = rig.intake.counters().misses;
  rig.steps(300);  // at rest within kStopFromVelocityLimitS (core/robot/robot.hpp)
  const std::array<double, kJointCount> held = rig.sent;
  rig.steps(100);
  EXPECT_EQ(rig.intake.counters().misses, misses) << "nobody owns the motion: no miss";
  EXPECT_EQ(rig.sent, held) << "the joints hold";
  EXPECT_EQ(rig.rescue->mode(), RcMode::idle) << "it waits for the operator";
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  rig.steps(10);
  EXPECT_EQ(rig.links->motion.owner.task(), 0);
  EXPECT_EQ(rig.intake.driving_task(), 0);
  EXPECT_EQ(rig.rescue->counters().predecessor_releases, 1U);
}

TEST(RcTasks, AnOwnerThatStallsAndComesBackTakesTheFreeMotionBack) {
  testing::RcTaskRig rig;
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  rig.steps(300);
  rig.rescue_runs = false;
  rig.steps(static_cast<int>(config::kOwnerDeadAfterPeriods) + 5);
  EXPECT_EQ(rig.links->motion.owner.task(), kNoOwnerTask);
  rig.rescue_runs = true;
  rig.steps(3);
  EXPECT_EQ(rig.links->motion.owner.task(), 0);
  EXPECT_EQ(rig.rescue->counters().retakes, 1U);
  EXPECT_EQ(rig.rescue->mode(), RcMode::approach) << "its motion goes on";
  EXPECT_EQ(rig.intake.driving_task(), 0);
}

TEST(RcTasks, AMotionReleasedAfterTheDrivesWatchdogWaitsForTheOperator) {
  // The handler's release after the drives' watchdog expired (a host stall longer than 100 ms,
  // docs/tasks.md "Liveness") holds the free motion for the operator: the owner, alive and still
  // the operator's choice, does not take it back by itself (as after its own stall) until `ctl owner`.
  testing::RcTaskRig rig;
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  rig.steps(300);
  const std::uint64_t word = rig.links->motion.owner.word();
  ASSERT_EQ(MotionOwner::task_of(word), 0);
  ASSERT_TRUE(rig.links->motion.owner.release_to_operator(word));
  rig.steps(200);
  EXPECT_EQ(rig.links->motion.owner.task(), kNoOwnerTask) << "the motion waits for the operator";
  EXPECT_EQ(rig.rescue->counters().retakes, 0U);
  EXPECT_EQ(rig.intake.driving_task(), kNoOwnerTask);
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  rig.steps(3);
  EXPECT_EQ(rig.links->motion.owner.task(), 0) << "the operator's take gives it again";
  EXPECT_FALSE(MotionOwner::held_for_operator(rig.links->motion.owner.word()));
  EXPECT_EQ(MotionOwner::generation_of(rig.links->motion.owner.word()), MotionOwner::generation_of(word) + 2);
  EXPECT_EQ(rig.rescue->counters().retakes, 0U) << "the operator's take, not a retake";
}

TEST(RcTasks, AnEndEffectorTargetMovesThatPalm) {
  testing::RcTaskRig rig;
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  rig.steps(1700);  // at the ready posture
  kin::LinkPoses poses;
  kin::forward_kinematics(rig.rescue->references(), poses);
  const kin::Vector3 right = poses[kin::kRightEe].p;
  const kin::Vector3 left = poses[kin::kLeftEe].p;
  const kin::Vector3 rpy = poses[kin::kRightEe].R.eulerAngles(2, 1, 0);
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::end_effector_target,
                       static_cast<std::uint8_t>(protocol::Effector::right_hand), 0,
                       {right.x() + 0.05, right.y(), right.z() + 0.03, rpy(2), rpy(1), rpy(0)}));
  rig.steps(1500);
  EXPECT_EQ(rig.rescue->mode(), RcMode::target);
  kin::forward_kinematics(rig.rescue->references(), poses);
  EXPECT_NEAR(poses[kin::kRightEe].p.x(), right.x() + 0.05, 2e-3);
  EXPECT_NEAR(poses[kin::kRightEe].p.z(), right.z() + 0.03, 2e-3);
  EXPECT_NEAR((poses[kin::kLeftEe].p - left).norm(), 0.0, 2e-3) << "the other palm holds";
}

}  // namespace
}  // namespace rescue::app
