// The joint manager's demand is a record of the shared segment, and its mode goes to the drives'
// mode of operation as it is. A demand whose mode or enable byte the joint manager never writes is
// damage (a stray write, a bit flip): refused and counted, the last whole demand kept; the next
// whole demand is taken as before.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "core/app/links/task_links.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::app {
namespace {

constexpr auto kCsp = static_cast<std::int8_t>(ControlMode::cyclic_position);

class DamagedDemand : public ::testing::Test {
 protected:
  DamagedDemand() : fw(dir.path) {}
  void SetUp() override {
    ASSERT_TRUE(fw.bring_up());
    fw.run_until_op();
    fw.initialize_robot();
    for (int i = 0; i < 100; ++i) fw.period();
    ASSERT_FALSE(fw.handler->safe_stopped());
    ASSERT_TRUE(fw.links->demand.try_read(whole));
  }
  // One handler cycle alone (the joint manager would overwrite the demand in its next period).
  void handler_cycle() {
    fw.rig->clock.sleep_until(fw.rig->bus.next_wakeup());
    (void)fw.handler->cycle();
  }

  testing::TempStateDir dir;
  SimulatedFirmware fw;
  RobotDemand whole{};
  const std::size_t elbow = joint_index_by_name("l_elbow");
};

TEST_F(DamagedDemand, AModeTheJointManagerNeverWritesNeverReachesTheDrive) {
  RobotDemand bad = whole;
  bad[elbow].mode = 3;  // profile velocity: the drive would run on its own profile
  fw.links->demand.write(bad);
  handler_cycle();
  EXPECT_EQ(fw.handler->outputs()[elbow].mode_of_operation, kCsp);
  EXPECT_EQ(fw.handler->damaged_demands(), 1u);
  EXPECT_FALSE(fw.handler->safe_stopped());
  fw.links->demand.write(whole);
  handler_cycle();
  EXPECT_EQ(fw.handler->outputs()[elbow].mode_of_operation, kCsp);
  EXPECT_EQ(fw.handler->damaged_demands(), 1u);
}

TEST_F(DamagedDemand, AnEnableByteOtherThanZeroOrOneIsRefusedAndTheLastWholeDemandKept) {
  RobotDemand bad = whole;
  const unsigned char byte = 0x80;
  std::memcpy(&bad[elbow].enable, &byte, 1);  // as a stray write leaves it in the segment
  bad[elbow].mode = static_cast<std::int8_t>(ControlMode::cyclic_torque);  // whole, but in a refused record
  fw.links->demand.write(bad);
  handler_cycle();
  EXPECT_EQ(fw.handler->damaged_demands(), 1u);
  EXPECT_EQ(fw.handler->outputs()[elbow].mode_of_operation, kCsp);
}

}  // namespace
}  // namespace rescue::app
