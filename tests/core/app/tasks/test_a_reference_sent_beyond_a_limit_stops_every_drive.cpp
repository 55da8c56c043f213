// A reference sent beyond a joint's speed, acceleration or jerk limit is a fault like any other
// limit (issue 33 item 4), on the whole simulated robot in virtual time: the Motion owner jumps
// l_elbow by 1 mrad in one period (1 rad/s from rest: 1000 rad/s^2). Through the intake's limiter (the
// firmware) the jump becomes a ramp and nothing stops; with the limiter bypassed
// (MotionIntakeSettings::limit_references false, a defect kept for this test) the handler's check of
// what it sent stops every drive, naming the joint and the limit (reference acceleration, against 5).
#include <gtest/gtest.h>

#include "core/app/tasks/motion_intake.hpp"
#include "core/kinematics/kinematic_model.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"

namespace rescue::app {
namespace {

const std::size_t kElbow = joint_index_by_name("l_elbow");

struct Outcome {
  bool safe_stopped{false};
  HandlerEvent stop{};
  bool saw_stop{false};
};

Outcome jump_the_elbow(const MotionIntakeSettings& intake) {
  Outcome out;
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  EXPECT_TRUE(fw.start_enabled(intake));
  const double start = fw.sample_of(kElbow).position_ref_rad;
  const std::uint64_t word = fw.links->motion.owner.take(0);
  for (int k = 0; k < 300; ++k) {
    fw.owner_period(0, word, kElbow, start + 0.001);
    fw.period();
  }
  out.safe_stopped = fw.handler->safe_stopped();
  HandlerEvent e{};
  while (fw.handler->pop_event(e)) {
    if (e.kind != HandlerEventKind::safe_stop) continue;
    out.saw_stop = true;
    out.stop = e;
  }
  return out;
}

TEST(SentReferenceLimits, ThroughTheLimiterAJumpIsARampAndNothingStops) {
  const Outcome out = jump_the_elbow(default_intake_settings());
  EXPECT_FALSE(out.safe_stopped);
  EXPECT_FALSE(out.saw_stop);
}

TEST(SentReferenceLimits, AReferenceSentBeyondTheAccelerationLimitStopsEveryDriveNamingJointAndLimit) {
  MotionIntakeSettings defect = default_intake_settings();
  defect.limit_references = false;
  const Outcome out = jump_the_elbow(defect);
  EXPECT_TRUE(out.safe_stopped);
  ASSERT_TRUE(out.saw_stop);
  EXPECT_EQ(out.stop.stop.first_joint, kElbow);
  EXPECT_EQ(out.stop.stop.first.reason, FaultReason::acceleration_reference_limit);
  EXPECT_DOUBLE_EQ(out.stop.stop.first.limit, kin::kJointAcceleration[kElbow]);
  EXPECT_GT(out.stop.stop.first.value, kin::kJointAcceleration[kElbow]);
}

}  // namespace
}  // namespace rescue::app
