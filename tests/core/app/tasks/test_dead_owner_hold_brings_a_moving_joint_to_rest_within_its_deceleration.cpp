// Issue 21 item 6, on the whole simulated robot in virtual time (the real EtherCAT handler and its
// motion intake, the real master, the simulated drives with their own position loop and motor): the
// Motion owner drives l_elbow at 1.2 rad/s and dies. Before, the intake stopped the joint's reference
// where the owner left it and the drive overshot it by about 0.1 rad on its own loop; now the
// reference decelerates within the joint's deceleration limit (core/robot/robot.hpp; at most its
// acceleration limit) to rest v^2/2a
// beyond the last owner reference, and the joint follows it: it passes its resting reference by no
// more than the drive's own loop adds on a ramp (its position loop has no velocity feed-forward:
// about 6 mrad here, a tenth of the abrupt stop's). The figures of both are printed
// (docs/motion-owner.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "core/app/tasks/motion_intake.hpp"
#include "core/kinematics/kinematic_model.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"

namespace rescue::app {
namespace {

constexpr double kSpeed = 1.2;  // rad/s, as in the killed-owner test's rescue motion
const std::size_t kElbow = joint_index_by_name("l_elbow");

struct DeadOwnerStop {
  double last_owner_reference{0.0};  // where the owner's references stopped
  double rest_reference{0.0};        // where the handler's reference came to rest
  double furthest{0.0};              // the joint's furthest actual position after the owner died
  double settled{0.0};               // its actual position 1.5 s after
  bool safe_stopped{false};          // the handler's check of what it sent stopped every drive
};

DeadOwnerStop stop_a_moving_joint(const MotionIntakeSettings& intake) {
  DeadOwnerStop out;
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  EXPECT_TRUE(fw.start_enabled(intake));
  double position = fw.sample_of(kElbow).position_ref_rad;
  // RC task 0 owns the motion and moves l_elbow at 1.2 rad/s for 0.5 s, one period per handler period
  // (reached at 4 rad/s^2, within the joint's acceleration limit: the intake passes it unchanged).
  MotionLinks& motion = fw.links->motion;
  const std::uint64_t word = motion.owner.take(0);
  RobotSample sample{};
  double speed = 0.0;
  for (int k = 0; k < 800; ++k) {
    speed = std::min(kSpeed, speed + 4.0 * 0.001);
    position += speed * 0.001;
    fw.owner_period(0, word, kElbow, position);
    fw.period();
  }
  out.last_owner_reference = position;
  // The owner dies: no reference, no heartbeat. 1.5 s of handler periods.
  out.furthest = -1e9;
  for (int k = 0; k < 1500; ++k) {
    fw.period();
    EXPECT_TRUE(fw.links->samples.try_read(sample));
    out.furthest = std::max(out.furthest, sample[kElbow].position_rad);
  }
  EXPECT_EQ(motion.owner.task(), kNoOwnerTask) << "the dead owner was released";
  out.safe_stopped = fw.handler->safe_stopped();
  out.rest_reference = sample[kElbow].position_ref_rad;
  out.settled = sample[kElbow].position_rad;
  return out;
}

TEST(DeadOwnerHold, AMovingJointComesToRestWithinItsDecelerationLimitWithoutOvershoot) {
  MotionIntakeSettings abrupt = default_intake_settings();
  abrupt.ramped_hold = false;
  const DeadOwnerStop before = stop_a_moving_joint(abrupt);
  const DeadOwnerStop after = stop_a_moving_joint(default_intake_settings());
  // The intake brings a joint to rest at the smaller of its deceleration and acceleration limits.
  const double a = std::min(deceleration_limit_rad_s2(kJoints[kElbow].limits), kin::kJointAcceleration[kElbow]);
  const double braking = kSpeed * kSpeed / (2.0 * a);  // what the deceleration limit implies
  std::printf("dead owner at %.1f rad/s, l_elbow (deceleration limit %.1f rad/s^2, stopping distance %.4f rad):\n",
              kSpeed, a, braking);
  std::printf("  abrupt reference stop: reference rests %.4f rad past the owner's last; joint overshoots it by %.4f rad\n",
              before.rest_reference - before.last_owner_reference, before.furthest - before.rest_reference);
  std::printf("  ramped (deceleration limit): reference rests %.4f rad past the owner's last; joint overshoots it by %.4f rad\n",
              after.rest_reference - after.last_owner_reference, after.furthest - after.rest_reference);
  // Before: the reference stopped dead (1.2 rad/s to rest in one period) and the drive's own loop
  // carried the joint 0.0726 rad past it (docs/motion-owner.md). Now such a reference is itself a
  // fault: the handler's check of what it sends (issue 33) stops every drive on it.
  EXPECT_TRUE(before.safe_stopped) << "an abrupt reference stop is a limit fault now";
  // After: the reference comes to rest v^2/2a (give or take the period the death is noticed in)
  // beyond the owner's last, and the joint stops there, overshooting it by what the drive's loop
  // adds on a ramp: within 0.01 rad; no safe stop.
  EXPECT_FALSE(after.safe_stopped);
  EXPECT_NEAR(after.rest_reference - after.last_owner_reference, braking, kSpeed * 0.002);
  EXPECT_LT(after.furthest - after.rest_reference, 0.01);
  EXPECT_NEAR(after.settled, after.rest_reference, 0.002);
}

}  // namespace
}  // namespace rescue::app
