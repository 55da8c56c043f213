// Issue 21 item 5, in virtual time on the whole simulated robot (the real EtherCAT handler, master
// and joint manager): the Motion owner drives l_elbow at 1.2 rad/s when the host stalls the handler
// for 300 ms, longer than the drives' 100 ms SyncManager watchdog. The drives stop (SAFE-OP, worm
// gears hold); when the handler runs again it re-arms them to OP and enables them again, each holding
// its actual position (its target is where it stands, not the reference from before the stall), and
// the Motion owner is released: the robot moves again only when the operator takes the motion
// (docs/tasks.md "Liveness").
#include <gtest/gtest.h>

#include <cmath>

#include "drivers/cia402/cia402_enable.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"

namespace rescue::app {
namespace {

const std::size_t kElbow = joint_index_by_name("l_elbow");

TEST(HandlerAfterWatchdog, DrivesComeBackHoldingTheirActualPositionAndTheOwnerIsReleased) {
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  ASSERT_TRUE(fw.start_enabled());
  double position = fw.sample_of(kElbow).position_ref_rad;
  RobotSample sample{};
  MotionLinks& motion = fw.links->motion;
  const std::uint64_t word = motion.owner.take(0);
  auto owner_period = [&]() {
    position += 1.2 * 0.001;
    fw.owner_period(0, word, kElbow, position);
  };
  for (int k = 0; k < 300; ++k) {
    owner_period();
    fw.period();
  }
  // The host stalls the handler 300 ms; the owner (another task) would go on, but its heartbeat is
  // refreshed by the test only after the stall, so only the watchdog rule is at work.
  fw.rig->clock.advance(300 * hal::kNsPerMs);
  bool enabled_again = false;
  double reference_at_enable = 0.0;
  double actual_at_enable = 0.0;
  for (int k = 0; k < 200 && !enabled_again; ++k) {
    owner_period();  // the owner keeps writing: its references must not be taken any more
    fw.period();
    ASSERT_TRUE(fw.links->samples.try_read(sample));
    if (k > 0 && drivers::is_enabled(fw.rig->drive(kElbow).drive().inputs().statusword)) {
      enabled_again = true;
      reference_at_enable = sample[kElbow].position_ref_rad;
      actual_at_enable = sample[kElbow].position_rad;
    }
  }
  ASSERT_TRUE(enabled_again) << "the drive was enabled again by itself";
  EXPECT_EQ(fw.handler->owners_released_after_watchdog(), 1U);
  EXPECT_EQ(motion.owner.task(), kNoOwnerTask) << "the motion waits for the operator";
  EXPECT_TRUE(MotionOwner::held_for_operator(motion.owner.word())) << "no RC task takes it back by itself";
  EXPECT_NEAR(reference_at_enable, actual_at_enable, 1e-4) << "enabled where it stands";
  // And it stays there: 0.5 s later it has not moved towards the owner's references.
  for (int k = 0; k < 500; ++k) {
    owner_period();
    fw.period();
  }
  ASSERT_TRUE(fw.links->samples.try_read(sample));
  EXPECT_NEAR(sample[kElbow].position_rad, actual_at_enable, 2e-3);
  EXPECT_LT(sample[kElbow].position_ref_rad, position - 0.5) << "the owner's references are not taken";
  EXPECT_EQ(fw.manager.statuses()[kElbow].state, fsm::JointState::enabled);
}

}  // namespace
}  // namespace rescue::app
