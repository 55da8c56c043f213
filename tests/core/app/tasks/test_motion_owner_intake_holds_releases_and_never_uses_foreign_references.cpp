// The Motion owner and the EtherCAT handler's intake (core/app/tasks/motion_intake.*, core/app/links/, docs/motion-owner.md), in
// virtual time, one handler period per millisecond:
//   the owner takes the motion and its references drive the joints it commands, through the limiter
//   (a jump becomes a ramp within the joint's limits, so these tests let a reference settle);
//   a missed deadline holds the last references and is counted; a joint the owner had in motion is
//   brought to rest within its deceleration limit first (no abrupt reference stop);
//   a dead owner is released within kOwnerDeadAfterPeriods + 1 periods and can be re-taken, also
//   when a damaged heartbeat (from the future, negative) lies over its last one; a stall of the whole
//   host (the handler held off its CPU as long as the owner) releases nobody;
//   a non-owner's references, references of an older owner word, and incomplete (torn) periods
//   never reach a joint; joints the handler does not drive are never commanded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>

#include "core/app/config/firmware_config.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/runtime/task_ports.hpp"
#include "core/app/tasks/motion_intake.hpp"
#include "core/kinematics/kinematic_model.hpp"

namespace rescue::app {
namespace {

constexpr hal::Nanoseconds kMs = hal::kNsPerMs;
const std::size_t kElbow = joint_index_by_name("l_elbow");
const std::size_t kNeck = joint_index_by_name("neck_pan");

struct Rig {
  std::unique_ptr<TaskLinks> links = std::make_unique<TaskLinks>();
  MotionIntake intake{motion_intake_ports(*links), default_intake_settings()};
  RobotDemand demand{};
  hal::Nanoseconds now{1000 * kMs};

  // RC task `task` completes one period commanding `joints` at `position` (its heartbeat too).
  void write(std::size_t task, double position, JointMask joints, bool complete = true) {
    ReferenceSpace& space = links->motion.references[task];
    space.begin();
    for (std::size_t j = 0; j < kJointCount; ++j) space.set(j, position);
    links->rc_heartbeat_ns[task].store(now);
    if (!complete) return;
    const std::uint64_t word = links->motion.owner.word();
    const bool owns = MotionOwner::task_of(word) == task;
    space.complete(owns ? word : 0, space.completed() + 1, joints, now);
  }
  const std::array<double, kJointCount>& handler_period(JointMask driven = kAllJoints) {
    const auto& refs = intake.period(now, demand, driven);
    now += kMs;
    return refs;
  }
  // The owner writes `position` every period for 0.5 s: the intake's limiter ramps there and rests.
  const std::array<double, kJointCount>& settle(std::size_t task, double position, JointMask joints,
                                                JointMask driven = kAllJoints) {
    for (int k = 0; k < 499; ++k) {
      write(task, position, joints);
      (void)handler_period(driven);
    }
    write(task, position, joints);
    return handler_period(driven);
  }
};

// An owner moving joint `j` from `from` at `speed`, reached within the joint's acceleration limit
// (so the intake's limiter passes it unchanged): the position it writes at period k.
double moving_reference(std::size_t j, double from, double speed, int k) {
  const double a = 0.8 * kin::kJointAcceleration[j];
  const double ramp = speed / a;
  const double t = (k + 1) * 0.001;
  return t < ramp ? from + 0.5 * a * t * t : from + 0.5 * a * ramp * ramp + speed * (t - ramp);
}

TEST(MotionIntake, WithoutOwnerEveryJointHoldsTheJointManagersReference) {
  Rig rig;
  rig.demand[kElbow].position_ref_rad = 0.7;
  EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.7);
  EXPECT_EQ(rig.intake.counters().misses, 0U);
  EXPECT_EQ(rig.intake.driving_task(), kNoOwnerTask);
}

TEST(MotionIntake, TheOwnersReferencesDriveTheJointsItCommands) {
  Rig rig;
  rig.demand[kNeck].position_ref_rad = 0.3;
  (void)rig.handler_period();
  const std::uint64_t word = rig.links->motion.owner.take(0);
  EXPECT_EQ(MotionOwner::task_of(word), 0);
  rig.write(0, 0.001, joint_bit(kElbow));
  const double first = rig.handler_period()[kElbow];
  EXPECT_GT(first, 0.0) << "towards the owner's reference";
  EXPECT_LE(first, kin::kJointAcceleration[kElbow] * 1e-6 + 1e-15) << "from rest within the acceleration limit";
  const auto& refs = rig.settle(0, 0.001, joint_bit(kElbow));
  EXPECT_DOUBLE_EQ(refs[kElbow], 0.001);
  EXPECT_DOUBLE_EQ(refs[kNeck], 0.3) << "a joint the owner does not command keeps the joint manager's reference";
  EXPECT_EQ(rig.intake.driving_task(), 0);
  EXPECT_EQ(rig.intake.counters().used_periods, 501U);
}

TEST(MotionIntake, AMissedDeadlineHoldsTheLastReferencesAndIsCounted) {
  Rig rig;
  (void)rig.links->motion.owner.take(0);
  EXPECT_DOUBLE_EQ(rig.settle(0, 0.001, kAllJoints)[kElbow], 0.001);  // at rest there: the hold is exact
  // The owner computes but does not complete its next periods in time: only its heartbeat moves.
  for (int k = 0; k < 5; ++k) {
    rig.links->rc_heartbeat_ns[0].store(rig.now);
    const auto& refs = rig.handler_period();
    EXPECT_DOUBLE_EQ(refs[kElbow], 0.001) << "hold position";
  }
  // Deadline 2 ms: the reference completed 1 ms before the first of those periods is still taken.
  EXPECT_EQ(rig.intake.counters().misses, 3U);
  EXPECT_EQ(rig.intake.counters().stale, 3U);
  EXPECT_EQ(rig.links->motion.owner_misses.load(), 3U);
  EXPECT_EQ(rig.links->motion.owner.task(), 0) << "a late owner is not a dead one";
  EXPECT_DOUBLE_EQ(rig.settle(0, 0.002, kAllJoints)[kElbow], 0.002);
  EXPECT_EQ(rig.intake.consecutive_misses(), 0U);
}

TEST(MotionIntake, ADeadOwnerIsReleasedWithinTheDocumentedPeriodsAndCanBeRetaken) {
  Rig rig;
  (void)rig.links->motion.owner.take(0);
  (void)rig.settle(0, 0.001, kAllJoints);  // at rest there: the hold is exact
  const hal::Nanoseconds last_beat = rig.now - kMs;
  // Task 0 dies: nothing more from it.
  int periods = 0;
  while (rig.links->motion.owner.task() == 0 && periods < 1000) {
    EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.001) << "held while dead";
    ++periods;
  }
  EXPECT_EQ(rig.links->motion.owner.task(), kNoOwnerTask);
  EXPECT_LE(rig.now - kMs - last_beat, (config::kOwnerDeadAfterPeriods + 1) * config::kRcTaskPeriodNs);
  EXPECT_LE(periods, config::kOwnerDeadAfterPeriods + 1);
  EXPECT_EQ(rig.intake.counters().releases, 1U);
  EXPECT_EQ(rig.links->motion.owner_releases.load(), 1U);
  // Released: no more misses counted, the joints hold.
  const std::uint64_t misses = rig.intake.counters().misses;
  EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.001);
  EXPECT_EQ(rig.intake.counters().misses, misses);
  // The restarted task (or another) takes it; its old period's references are never reused.
  std::uint64_t word = 0;
  ASSERT_TRUE(rig.links->motion.owner.take_if_free(1, word));
  EXPECT_FALSE(rig.links->motion.owner.take_if_free(0, word)) << "only a free motion is taken that way";
  EXPECT_DOUBLE_EQ(rig.settle(1, 0.0015, kAllJoints)[kElbow], 0.0015);
  EXPECT_EQ(rig.intake.driving_task(), 1);
}

// Issue 35 item 8: the owner's heartbeat is a record of the shared segment. A damaged one over a
// dead owner's last beat (a time far in the future read as "beat just now" for good; a negative one,
// whose age overflowed) is counted, and the owner released by the handler's own periods as before.
TEST(MotionIntake, ADeadOwnerBehindADamagedHeartbeatIsReleasedAndTheDamageCounted) {
  for (const std::int64_t damage : {std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min()}) {
    Rig rig;
    (void)rig.links->motion.owner.take(0);
    (void)rig.settle(0, 0.001, kAllJoints);
    rig.links->rc_heartbeat_ns[0].store(damage);  // task 0 dies; a stray write lands on its beat
    int periods = 0;
    while (rig.links->motion.owner.task() == 0 && periods < 1000) {
      EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.001) << "held while dead";
      ++periods;
    }
    EXPECT_EQ(rig.links->motion.owner.task(), kNoOwnerTask) << damage;
    EXPECT_LE(periods, config::kOwnerDeadAfterPeriods + 1) << damage;
    EXPECT_EQ(rig.intake.counters().releases, 1U);
    EXPECT_EQ(rig.intake.counters().damaged_beats, 1U);
  }
}

// Issue 35 (load stage): every task, the handler too, held off its CPUs for 218 ms by a loaded host.
// On the wall clock the owner's heartbeat is 218 ms old when the handler runs again, but the handler
// ran no period in between either: that is jitter, not a dead owner. The owner keeps the motion,
// and the first periods after the stall only hold (its references are late) until it writes again.
TEST(MotionIntake, AStallOfTheWholeHostReleasesNoOwner) {
  Rig rig;
  (void)rig.links->motion.owner.take(0);
  (void)rig.settle(0, 0.001, kAllJoints);
  rig.now += 218 * kMs;  // nobody ran: neither the owner nor the handler
  EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.001) << "held: the owner's period is late";
  EXPECT_EQ(rig.links->motion.owner.task(), 0) << "a stalled host is not a dead owner";
  EXPECT_EQ(rig.intake.counters().releases, 0U);
  // The owner runs again: its references drive the joint at once.
  EXPECT_DOUBLE_EQ(rig.settle(0, 0.002, kAllJoints)[kElbow], 0.002);
  EXPECT_EQ(rig.intake.driving_task(), 0);
  // A real death after that is still released within the documented periods of the handler.
  int periods = 0;
  while (rig.links->motion.owner.task() == 0 && periods < 1000) {
    (void)rig.handler_period();
    ++periods;
  }
  EXPECT_EQ(rig.links->motion.owner.task(), kNoOwnerTask);
  EXPECT_LE(periods, config::kOwnerDeadAfterPeriods + 1);
}

// Issue 21 item 6: an owner that dies while its joint moves at 1.2 rad/s. Its references stop; the
// joint's reference does not stop with them (an abrupt stop, which the drive overshoots) but
// decelerates at the joint's rest deceleration (the smaller of its deceleration and acceleration
// limits) to rest, v^2 / 2a beyond the last reference, then holds.
TEST(MotionIntake, AJointTheDeadOwnerMovedComesToRestWithinItsDecelerationLimit) {
  Rig rig;
  rig.demand[kElbow].position_ref_rad = 0.5;
  (void)rig.handler_period();
  (void)rig.links->motion.owner.take(0);
  constexpr double kSpeed = 1.2;  // rad/s, below l_elbow's 2 rad/s
  double position = 0.5;
  for (int k = 0; k < 500; ++k) {
    position = moving_reference(kElbow, 0.5, kSpeed, k);
    rig.write(0, position, joint_bit(kElbow));
    EXPECT_NEAR(rig.handler_period()[kElbow], position, 1e-9);
  }
  // Dead: nothing more from task 0. The reference slows by at most a * dt each period, never reverses.
  const double a = std::min(deceleration_limit_rad_s2(kJoints[kElbow].limits), kin::kJointAcceleration[kElbow]);
  double previous = position;
  double previous_step = kSpeed * 0.001;
  int moving = 0;
  for (int k = 0; k < 1000; ++k) {
    const double ref = rig.handler_period()[kElbow];
    const double step = ref - previous;
    EXPECT_GE(step, 0.0) << "never backwards";
    EXPECT_LE(previous_step - step, a * 0.001 * 0.001 + 1e-12) << "within the deceleration limit, period " << k;
    if (step > 0.0) ++moving;
    previous_step = step;
    previous = ref;
  }
  EXPECT_EQ(rig.links->motion.owner.task(), kNoOwnerTask) << "released meanwhile";
  // At rest after v / a (1.2 / 5 = 0.24 s), v^2 / 2a (0.144 rad) beyond the last reference.
  EXPECT_NEAR(moving, kSpeed / a * 1000.0, 2.0);
  EXPECT_NEAR(previous - position, kSpeed * kSpeed / (2.0 * a), 1e-3);
  EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], previous) << "then holds";
}

TEST(MotionIntake, WithoutTheRampADeadOwnersJointStopsAbruptly) {
  MotionIntakeSettings abrupt = default_intake_settings();
  abrupt.ramped_hold = false;
  Rig rig;
  MotionIntake intake{motion_intake_ports(*rig.links), abrupt};
  rig.demand[kElbow].position_ref_rad = 0.5;
  (void)intake.period(rig.now, rig.demand, kAllJoints);
  rig.now += kMs;
  (void)rig.links->motion.owner.take(0);
  double sent = 0.5;
  for (int k = 0; k < 500; ++k) {
    rig.write(0, moving_reference(kElbow, 0.5, 1.2, k), joint_bit(kElbow));
    sent = intake.period(rig.now, rig.demand, kAllJoints)[kElbow];
    rig.now += kMs;
  }
  EXPECT_DOUBLE_EQ(intake.period(rig.now, rig.demand, kAllJoints)[kElbow], sent) << "stops where it was sent last";
}

TEST(MotionIntake, ANonOwnersReferencesNeverReachAJoint) {
  Rig rig;
  rig.demand[kElbow].position_ref_rad = 0.5;
  (void)rig.links->motion.owner.take(0);
  rig.write(0, 0.5, kAllJoints);
  for (int k = 0; k < 10; ++k) {
    rig.write(1, 0.4, kAllJoints);  // the teleop task computes every period without owning
    rig.write(0, 0.5, kAllJoints);
    EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.5);
  }
  EXPECT_EQ(rig.intake.counters().misses, 0U);
  // References task 1 wrote while task 0 owned are not its own after a handover: never used.
  (void)rig.links->motion.owner.take(1);
  EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.5);
  EXPECT_EQ(rig.intake.counters().foreign, 1U);
  // References of an older word of the same task are not used either.
  const std::uint64_t old_word = rig.links->motion.owner.word();
  (void)rig.links->motion.owner.take(0);
  (void)rig.links->motion.owner.take(1);
  ReferenceSpace& space = rig.links->motion.references[1];
  space.begin();
  space.set(kElbow, 0.45);
  space.complete(old_word, 99, kAllJoints, rig.now);
  EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.5);
  EXPECT_EQ(rig.intake.counters().foreign, 2U);
}

TEST(MotionIntake, IncompleteOrNeverWrittenReferencesAreNeverUsed) {
  Rig rig;
  (void)rig.links->motion.owner.take(0);
  rig.links->rc_heartbeat_ns[0].store(rig.now);
  EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.0) << "never written";
  EXPECT_DOUBLE_EQ(rig.settle(0, 0.001, kAllJoints)[kElbow], 0.001);  // at rest there: the hold is exact
  // A period begun but never completed (the writer died or is mid-write): the sequence stays odd.
  rig.write(0, 0.0015, kAllJoints, /*complete=*/false);
  ReferenceSnapshot copy;
  EXPECT_FALSE(rig.links->motion.references[0].read(copy));
  EXPECT_DOUBLE_EQ(rig.handler_period()[kElbow], 0.001);
  EXPECT_EQ(rig.intake.counters().incomplete, 2U);
  // The restarted writer completes its next period cleanly.
  rig.write(0, 0.002, kAllJoints);
  EXPECT_TRUE(rig.links->motion.references[0].read(copy));
  EXPECT_DOUBLE_EQ(rig.settle(0, 0.002, kAllJoints)[kElbow], 0.002);
}

TEST(MotionIntake, JointsTheHandlerDoesNotDriveAreNeverCommanded) {
  Rig rig;
  rig.demand[kElbow].position_ref_rad = 0.25;  // a lost joint's held reference
  rig.demand[kNeck].position_ref_rad = 0.259;
  (void)rig.links->motion.owner.take(0);
  rig.write(0, 0.26, kAllJoints);
  const JointMask driven = kAllJoints & ~joint_bit(kElbow);
  const auto& refs = rig.settle(0, 0.26, kAllJoints, driven);
  EXPECT_DOUBLE_EQ(refs[kElbow], 0.25);
  EXPECT_DOUBLE_EQ(refs[kNeck], 0.26);
}

TEST(MotionIntake, ReferencesAreLimitedInPositionSpeedAndAcceleration) {
  Rig rig;
  (void)rig.handler_period();  // the joints driven from the joint manager's reference first
  (void)rig.links->motion.owner.take(0);
  rig.write(0, 1.0, kAllJoints);  // a jump: 1 rad in one period
  const auto& refs = rig.handler_period();
  EXPECT_NEAR(refs[kElbow], kin::kJointAcceleration[kElbow] * 1e-6, 1e-12) << "from rest at the acceleration limit";
  EXPECT_GT(rig.intake.counters().clamped, 0U);
  double previous = refs[kElbow];
  double fastest = 0.0;
  for (int k = 0; k < 1000; ++k) {
    rig.write(0, 1.0, kAllJoints);
    const double ref = rig.handler_period()[kElbow];
    fastest = std::max(fastest, (ref - previous) / 1e-3);
    previous = ref;
  }
  EXPECT_NEAR(fastest, kJoints[kElbow].limits.velocity_max_rad_s, 1e-9) << "at most the velocity limit";
  rig.write(0, 100.0, kAllJoints);
  for (int k = 0; k < 5000; ++k) {
    rig.links->rc_heartbeat_ns[0].store(rig.now);
    rig.write(0, 100.0, kAllJoints);
    (void)rig.handler_period();
  }
  EXPECT_DOUBLE_EQ(rig.intake.period(rig.now, rig.demand, kAllJoints)[kElbow], kJoints[kElbow].limits.position_max_rad);
}

TEST(MotionOwner, ReleaseNeverUndoesANewerTake) {
  MotionOwner owner;
  const std::uint64_t first = owner.take(0);
  const std::uint64_t second = owner.take(1);
  EXPECT_NE(first, second);
  EXPECT_FALSE(owner.release(first));
  EXPECT_EQ(owner.task(), 1);
  EXPECT_TRUE(owner.release(second));
  EXPECT_EQ(owner.task(), kNoOwnerTask);
  EXPECT_GT(MotionOwner::generation_of(owner.word()), MotionOwner::generation_of(second));
}

}  // namespace
}  // namespace rescue::app
