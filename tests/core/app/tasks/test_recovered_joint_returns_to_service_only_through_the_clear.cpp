// Online recovery seen by the firmware's tasks (real master, real joint manager, real error-joints
// file, the simulated robot in virtual time): a power-cycled drive is lost and recorded in the
// file, the master brings it back to OP by itself and the joint is reachable again ("available"),
// but it stays in Error, out of service, and the file keeps it, until the operator's clear: then
// the file drops it durably, the joint goes to Idle and can be enabled again. The other joints keep
// every period throughout. When the configuration says so, a joint whose drive was power-cycled is
// cleared and reset automatically; joints lost through a cable are not.
#include <gtest/gtest.h>

#include "core/app/tasks/predefined_messages.hpp"
#include "drivers/cia402/cia402_enable.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"

namespace rescue::app {
namespace {

JointMask recorded_in_file(ErrorJointsFileStorage& storage) {
  const ErrorJointsLoad file = storage.load();
  JointMask recorded = 0;
  for (const auto& record : file.decoded.contents.records) recorded |= joint_bit(record.joint);
  return recorded;
}

TEST(RecoveredJoint, ReturnsToServiceOnlyThroughTheOperatorsClear) {
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  ecat::MasterOptions options;
  options.online_recovery = true;
  ASSERT_TRUE(fw.bring_up(options)) << rescue::testing::describe_master_failure(fw.rig->bus.master());
  fw.run_until_op();
  fw.initialize_robot();
  for (int i = 0; i < 100; ++i) fw.period();
  const std::size_t elbow = joint_index_by_name("l_elbow");
  const JointMask bit = joint_bit(elbow);
  ASSERT_EQ(fw.manager.statuses()[elbow].state, fsm::JointState::enabled);

  const std::size_t position = slave_position_of_joint(elbow);
  ASSERT_TRUE(fw.rig->segment.power_cycle(position, fw.rig->clock.now()).ok());
  for (int i = 0; i < 50; ++i) fw.period();
  EXPECT_EQ(fw.manager.lost_joints(), bit);
  EXPECT_EQ(recorded_in_file(fw.storage), bit);
  const std::uint64_t writes_after_loss = fw.manager.recorded().sequence;

  // The master brings the drive back by itself: reachable again, still out of service.
  for (int i = 0; i < 400 && fw.rig->bus.master().recovery_stats().recovered == 0; ++i) fw.period();
  ASSERT_EQ(fw.rig->bus.master().recovery_stats().recovered, 1u);
  for (int i = 0; i < 500; ++i) fw.period();
  EXPECT_EQ(fw.rig->segment.esc(position).al_state(), ecat::reg::AlState::op);
  EXPECT_EQ(fw.manager.statuses()[elbow].state, fsm::JointState::error);
  EXPECT_EQ(fw.manager.lost_joints(), bit);
  EXPECT_EQ(recorded_in_file(fw.storage), bit) << "the file changes only through the clear";
  EXPECT_EQ(fw.manager.recorded().sequence, writes_after_loss);
  EXPECT_FALSE(drivers::is_enabled(fw.rig->drive(elbow).drive().inputs().statusword)) << "its drive stays disabled";
  EXPECT_EQ(fw.handler->missed_cycles(kAllJoints & ~joints_of_branch(kJoints[elbow].branch)), 0u);
  // Behind it on its branch: only the frame that first showed the short counter (one slave short cannot
  // be told from a cut there); from the next frame the probes place the shortfall on l_elbow alone.
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints_lost_by_link_failure_at(elbow) & ~bit & joint_bit(j)) == 0) continue;
    EXPECT_LE(fw.handler->missed_cycles(joint_bit(j)), 1u) << kJoints[j].name;
  }

  // The operator's clear: the file drops it (durably), the joint goes to Idle.
  for (const JointCommand& c : clear_repaired_joints_commands(bit)) ASSERT_TRUE(fw.parser.try_send(c));
  for (int i = 0; i < 20; ++i) fw.period();
  EXPECT_EQ(fw.manager.lost_joints(), 0u);
  EXPECT_EQ(recorded_in_file(fw.storage), 0u);
  EXPECT_EQ(fw.manager.statuses()[elbow].state, fsm::JointState::idle);
  for (const JointCommand& c : initialize_robot_commands(bit)) ASSERT_TRUE(fw.parser.try_send(c));
  for (int i = 0; i < 200; ++i) fw.period();
  EXPECT_EQ(fw.manager.statuses()[elbow].state, fsm::JointState::enabled);
  EXPECT_TRUE(drivers::is_enabled(fw.rig->drive(elbow).drive().inputs().statusword));
}

TEST(RecoveredJoint, APowerCycledDriveIsClearedAutomaticallyWhenConfiguredButACableLossIsNot) {
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  fw.manager.set_auto_clear_power_cycled(true);
  ecat::MasterOptions options;
  options.online_recovery = true;
  ASSERT_TRUE(fw.bring_up(options));
  fw.run_until_op();
  fw.initialize_robot();
  for (int i = 0; i < 100; ++i) fw.period();
  const std::size_t neck = joint_index_by_name("neck_pan");
  ASSERT_TRUE(fw.rig->segment.power_cycle(slave_position_of_joint(neck), fw.rig->clock.now()).ok());
  for (int i = 0; i < 10; ++i) fw.period();
  EXPECT_EQ(recorded_in_file(fw.storage), joint_bit(neck));
  for (int i = 0; i < 400 && fw.manager.lost_joints() != 0; ++i) fw.period();
  EXPECT_EQ(fw.manager.lost_joints(), 0u);
  EXPECT_EQ(recorded_in_file(fw.storage), 0u);
  EXPECT_EQ(fw.manager.statuses()[neck].state, fsm::JointState::idle);

  // A cable cut and restored: the drives kept their power, so the operator must clear them.
  const std::size_t wrist = joint_index_by_name("r_wrist_yaw");
  const JointMask tail = joints_lost_by_link_failure_at(wrist);
  ASSERT_TRUE(fw.rig->segment.cut_link(slave_position_of_joint(wrist)).ok());
  for (int i = 0; i < 300; ++i) fw.period();
  ASSERT_EQ(fw.manager.lost_joints(), tail);
  ASSERT_TRUE(fw.rig->segment.restore_link(slave_position_of_joint(wrist)).ok());
  for (int i = 0; i < 600; ++i) fw.period();
  EXPECT_EQ(fw.rig->bus.master().recovering(), 0u) << "back in OP";
  EXPECT_EQ(fw.manager.lost_joints(), tail);
  EXPECT_EQ(recorded_in_file(fw.storage), tail);
}

}  // namespace
}  // namespace rescue::app
