// An owner change while joints move is bumpless in speed, not only in position (core/app/tasks/
// rc_task.hpp, docs/motion-owner.md): the new owner's references start from the references being
// sent AND their speed (the handler publishes it as JointSample::velocity_ref_rad_s), so
//   - its first reference continues the sent motion: within a_max dt^2 of sent + v dt;
//   - the teleop task taking a moving arm with no command brakes it at its acceleration limit,
//     never backwards (before, it took over at rest: its own references stopped dead, and what was
//     sent came to rest past the take-over point and came back);
//   - every reference sent, over a sequence of owner changes (rescue approach -> teleop -> rescue
//     -> teleop closing a hand -> rescue -> teleop), keeps every joint's speed, acceleration and,
//     where it declares one, jerk limit, judged here from the positions sent.
// Virtual time (tests/support/rc_task_rig.hpp): the two RC tasks and the handler's intake.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/support/rc_task_rig.hpp"

namespace rescue::app {
namespace {

constexpr double kDt = 0.001;
const std::size_t kLeftHand = joint_index_by_name("l_hand");

// The joints the rescue task commands: the IK's.
JointMask ik_joints() {
  JointMask mask = 0;
  for (const std::size_t j : kin::kIkJoints) mask |= joint_bit(j);
  return mask;
}

// Every reference sent, judged from the positions alone: speed, acceleration, jerk.
struct SentJudge {
  std::array<double, kJointCount> previous{};
  std::array<double, kJointCount> speed{};
  std::array<double, kJointCount> acceleration{};
  int history{0};
  double worst_speed_ratio{0.0};
  double worst_acceleration_ratio{0.0};
  double worst_jerk_ratio{0.0};

  void judge(const testing::RcTaskRig& rig) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((rig.driven() & joint_bit(j)) == 0) continue;
      const double v = (rig.sent[j] - previous[j]) / kDt;
      const double a = (v - speed[j]) / kDt;
      const double jerk = (a - acceleration[j]) / kDt;
      if (history >= 1) worst_speed_ratio = std::max(worst_speed_ratio, std::fabs(v) / kJoints[j].limits.velocity_max_rad_s);
      if (history >= 2) worst_acceleration_ratio = std::max(worst_acceleration_ratio, std::fabs(a) / kin::kJointAcceleration[j]);
      if (history >= 3 && kin::kJointJerk[j] > 0.0) {
        worst_jerk_ratio = std::max(worst_jerk_ratio, std::fabs(jerk) / kin::kJointJerk[j]);
      }
      speed[j] = v;
      acceleration[j] = a;
      previous[j] = rig.sent[j];
    }
    ++history;
  }
  void step(testing::RcTaskRig& rig, int n = 1) {
    for (int k = 0; k < n; ++k) {
      rig.step();
      judge(rig);
    }
  }
};

// The joint of `mask` whose reference is sent fastest now.
std::size_t fastest(const testing::RcTaskRig& rig, JointMask mask) {
  std::size_t best = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((mask & joint_bit(j)) != 0 && std::fabs(rig.intake.sent_speed(j)) > std::fabs(rig.intake.sent_speed(best))) best = j;
  }
  return best;
}

// `task` takes the motion; returns after its first period as the owner. Its references that period
// continue every moving joint it commands: within a_max dt^2 of where the sent speed carries it.
void take_and_expect_continuation(testing::RcTaskRig& rig, SentJudge& judge, RcTaskId task, JointMask commanded) {
  const std::array<double, kJointCount> sent = rig.sent;
  std::array<double, kJointCount> speed{};
  for (std::size_t j = 0; j < kJointCount; ++j) speed[j] = rig.intake.sent_speed(j);
  ASSERT_TRUE(rig.send(task, RcInputKind::take_ownership));
  judge.step(rig);
  ASSERT_EQ(rig.links->motion.owner.task(), static_cast<std::uint8_t>(task));
  const kin::JointVector& own = task == RcTaskId::rescue ? rig.rescue->references() : rig.teleop->references();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((commanded & joint_bit(j)) == 0) continue;
    const double carried = sent[j] + speed[j] * kDt;
    EXPECT_LE(std::fabs(own(static_cast<Eigen::Index>(j)) - carried), kin::kJointAcceleration[j] * kDt * kDt * (1.0 + 1e-6) + 1e-12)
        << kJoints[j].name << " taken at " << speed[j] << " rad/s";
  }
}

TEST(OwnerChange, TeleopTakingAMovingArmBrakesItAtItsLimitAndNeverBackwards) {
  testing::RcTaskRig rig;
  SentJudge judge;
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  judge.step(rig, 800);  // the middle of the approach: the arms at speed
  const std::size_t moving = fastest(rig, ik_joints());
  const double speed_at_take = rig.intake.sent_speed(moving);
  ASSERT_GT(std::fabs(speed_at_take), 0.1) << kJoints[moving].name;
  take_and_expect_continuation(rig, judge, RcTaskId::teleop, rig.driven());
  // No teleop command: the joint brakes from its speed at its acceleration limit (its step shrinks
  // by at most a_max dt^2 a period, by exactly that while it moves) and never turns back.
  double step = judge.speed[moving] * kDt;  // the take's period
  const double a_step = kin::kJointAcceleration[moving] * kDt * kDt;
  int periods = 0;
  while (std::fabs(step) > 0.0 && periods < 2000) {
    const double before = rig.sent[moving];
    judge.step(rig);
    const double now_step = rig.sent[moving] - before;
    EXPECT_GE(now_step * speed_at_take, 0.0) << "never backwards";
    EXPECT_LE(std::fabs(now_step), std::fabs(step) + 1e-12);
    EXPECT_LE(std::fabs(step) - std::fabs(now_step), a_step * (1.0 + 1e-6) + 1e-12);
    step = now_step;
    ++periods;
  }
  // At rest after |v| / a_max (and a period for the rounding).
  EXPECT_LE(periods, static_cast<int>(std::ceil(std::fabs(speed_at_take) / kin::kJointAcceleration[moving] / kDt)) + 2);
  EXPECT_FALSE(rig.intake.violation().active());
  EXPECT_LE(judge.worst_speed_ratio, 1.0 + 1e-9);
  EXPECT_LE(judge.worst_acceleration_ratio, 1.0 + 1e-6);
}

TEST(OwnerChange, EveryReferenceSentKeepsEveryLimitOverOwnerChangesWhileJointsMove) {
  testing::RcTaskRig rig;
  SentJudge judge;
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::take_ownership));
  judge.step(rig, 700);
  // Teleop takes the moving arms; 30 ms later (still braking) the rescue task takes them back: it
  // restarts its approach from the references sent and their speed.
  take_and_expect_continuation(rig, judge, RcTaskId::teleop, rig.driven());
  judge.step(rig, 30);
  const std::size_t moving = fastest(rig, ik_joints());
  EXPECT_GT(std::fabs(rig.intake.sent_speed(moving)), 0.05) << kJoints[moving].name << " still moving";
  take_and_expect_continuation(rig, judge, RcTaskId::rescue, ik_joints());
  judge.step(rig, 300);
  // The operator closes the left hand through teleop (jerk-limited), then the rescue task takes the
  // motion while the hand moves (it does not command the hands: the intake brakes it), then teleop
  // takes it back while the hand is still braking, and its command goes on.
  ASSERT_TRUE(rig.send(RcTaskId::teleop, RcInputKind::hand, 0, static_cast<std::uint8_t>(protocol::HandAction::close)));
  take_and_expect_continuation(rig, judge, RcTaskId::teleop, rig.driven());
  judge.step(rig, 400);
  EXPECT_GT(std::fabs(rig.intake.sent_speed(kLeftHand)), 0.4) << "the hand closes";
  take_and_expect_continuation(rig, judge, RcTaskId::rescue, ik_joints());
  judge.step(rig, 40);
  EXPECT_GT(std::fabs(rig.intake.sent_speed(kLeftHand)), 0.05) << "still braking";
  take_and_expect_continuation(rig, judge, RcTaskId::teleop, rig.driven());
  judge.step(rig, 1500);
  std::printf("worst sent ratios over the owner changes: speed %.6f acceleration %.6f jerk %.6f\n",
              judge.worst_speed_ratio, judge.worst_acceleration_ratio, judge.worst_jerk_ratio);
  EXPECT_FALSE(rig.intake.violation().active());
  EXPECT_LE(judge.worst_speed_ratio, 1.0 + 1e-9);
  EXPECT_LE(judge.worst_acceleration_ratio, 1.0 + 1e-6);
  EXPECT_LE(judge.worst_jerk_ratio, 1.0 + 1e-6);
  EXPECT_GT(judge.worst_jerk_ratio, 0.0) << "a jerk-limited joint moved";
  EXPECT_EQ(rig.rescue->counters().kinematics_errors, 0U);
}

}  // namespace
}  // namespace rescue::app
