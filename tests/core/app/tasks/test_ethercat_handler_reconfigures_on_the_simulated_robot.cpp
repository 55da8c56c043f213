// The EtherCAT handler task with the real master, the real joint manager and the real error-joints
// file, on the whole simulated robot in virtual time (one thread steps both tasks, handler first):
// a link cut anywhere loses exactly the joints behind it, the file records them, the joint manager
// marks them, and the joints of every other branch bring valid data in every cycle.
#include <gtest/gtest.h>

#include <memory>

#include "core/app/links/task_links.hpp"
#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/predefined_messages.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "drivers/cia402/cia402_enable.hpp"
#include "drivers/joint/joint_units.hpp"
#include "hal/time/wall_clock.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::app {
namespace {

void cut_and_reconfigure(const char* joint_name) {
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  ASSERT_TRUE(fw.rig->built.ok());
  ASSERT_TRUE(fw.bring_up()) << rescue::testing::describe_master_failure(fw.rig->bus.master());
  fw.run_until_op();
  fw.initialize_robot();
  for (int i = 0; i < 100; ++i) fw.period();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    ASSERT_EQ(fw.manager.statuses()[j].state, fsm::JointState::enabled) << kJoints[j].name;
  }

  const std::size_t cut = joint_index_by_name(joint_name);
  const JointMask expected = joints_lost_by_link_failure_at(cut);
  ASSERT_TRUE(fw.rig->segment.cut_link(slave_position_of_joint(cut)).ok());
  for (int i = 0; i < 50; ++i) fw.period();

  EXPECT_EQ(fw.manager.lost_joints(), expected) << joint_name;
  EXPECT_EQ(fw.handler->tracker().confirmed(), expected);
  EXPECT_EQ(fw.handler->missed_cycles(kAllJoints & ~expected), 0u) << "a healthy joint missed a cycle";
  EXPECT_EQ(fw.handler->frames_missing(), 0u);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const bool lost = (expected & joint_bit(j)) != 0;
    EXPECT_EQ(fw.manager.statuses()[j].state, lost ? fsm::JointState::error : fsm::JointState::enabled)
        << kJoints[j].name;
  }
  const ErrorJointsLoad file = fw.storage.load();
  ASSERT_TRUE(file.file_present);
  JointMask recorded = 0;
  for (const auto& record : file.decoded.contents.records) recorded |= joint_bit(record.joint);
  EXPECT_EQ(recorded, expected);
}

TEST(EthercatHandlerOnSimulatedRobot, LinkCutAtElbowLosesTheForearm) { cut_and_reconfigure("l_elbow"); }
TEST(EthercatHandlerOnSimulatedRobot, LinkCutAtWaistLosesTheTorso) { cut_and_reconfigure("waist_yaw"); }
TEST(EthercatHandlerOnSimulatedRobot, LinkCutAtRightShoulderLosesTheRightArm) { cut_and_reconfigure("r_shoulder_pitch"); }
TEST(EthercatHandlerOnSimulatedRobot, LinkCutAtLastTrackLosesOnlyIt) { cut_and_reconfigure("r_track"); }

TEST(EthercatHandlerOnSimulatedRobot, RestartWithTheFileKeepsLostJointsOut) {
  testing::TempStateDir dir;
  const JointMask expected = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));
  {
    SimulatedFirmware fw(dir.path);
    ASSERT_TRUE(fw.bring_up());
    fw.run_until_op();
    ASSERT_TRUE(fw.rig->segment.cut_link(slave_position_of_joint(joint_index_by_name("l_elbow"))).ok());
    for (int i = 0; i < 50; ++i) fw.period();
    ASSERT_EQ(fw.manager.lost_joints(), expected);
  }
  SimulatedFirmware again(dir.path);  // a new robot: every cable intact again
  ASSERT_TRUE(again.bring_up()) << rescue::testing::describe_master_failure(again.rig->bus.master());
  EXPECT_EQ(again.restored, expected);
  again.run_until_op();
  again.initialize_robot();
  for (int i = 0; i < 100; ++i) again.period();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const bool lost = (expected & joint_bit(j)) != 0;
    EXPECT_EQ(again.manager.statuses()[j].state, lost ? fsm::JointState::error : fsm::JointState::enabled)
        << kJoints[j].name;
  }
  EXPECT_EQ(again.handler->missed_cycles(kAllJoints & ~expected), 0u);
}

TEST(EthercatHandlerOnSimulatedRobot, OwnLimitCheckStopsEveryDrive) {
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  ASSERT_TRUE(fw.bring_up());
  fw.run_until_op();
  fw.initialize_robot();
  for (int i = 0; i < 100; ++i) fw.period();
  ASSERT_FALSE(fw.handler->safe_stopped());

  // A demand far beyond l_elbow's position limit, as a faulty task could publish it; the handler
  // must stop the robot whatever the joint manager does.
  RobotDemand bad{};
  ASSERT_TRUE(fw.links->demand.try_read(bad));
  const std::size_t elbow = joint_index_by_name("l_elbow");
  bad[elbow].position_ref_rad = kJoints[elbow].limits.position_max_rad + 1.0;
  fw.links->demand.write(bad);
  fw.rig->clock.sleep_until(fw.rig->bus.next_wakeup());
  (void)fw.handler->cycle();
  EXPECT_TRUE(fw.handler->safe_stopped());
  HandlerEvent e{};
  bool saw_stop = false;
  while (fw.handler->pop_event(e)) saw_stop = saw_stop || e.kind == HandlerEventKind::safe_stop;
  EXPECT_TRUE(saw_stop);
  for (int i = 0; i < 100; ++i) {
    fw.rig->clock.sleep_until(fw.rig->bus.next_wakeup());
    (void)fw.handler->cycle();
  }
  for (std::size_t j = 0; j < kJointCount; ++j) {
    EXPECT_FALSE(drivers::is_enabled(fw.rig->drive(j).drive().inputs().statusword))
        << kJoints[j].name << " still enabled after the safe stop";
  }
}

}  // namespace
}  // namespace rescue::app
