// The joint manager's commands (the parser's queue) and lost-joint reports (the handler's queue) are
// records of the shared segment. A record whose kind, input, mode or step no writer writes, or that
// names a joint beyond the robot, is damage (a stray write, a bit flip): refused whole and counted,
// nothing applied and nothing recorded as lost; the next whole record is taken as before.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

using fsm::JointInput;
using fsm::JointState;

const std::size_t kElbow = joint_index_by_name("l_elbow");

class JointManagerDamagedRecords : public testing::JointManagerFixture {
 protected:
  // Every joint in Ready: CSP selected, the reference where it stands; enable would be taken.
  void ready_robot() {
    select_csp_at_current_position();
    step();
    ASSERT_EQ(manager.statuses()[kElbow].state, JointState::ready);
  }
  // Pushes `c` as it is, steps, and checks that nothing but the damage counter changed.
  void expect_refused_whole(const JointCommand& c) {
    const std::array<JointStatus, kJointCount> before = manager.statuses();
    const std::uint32_t refused = manager.refused_commands();
    const std::uint32_t damaged = manager.damaged_records();
    ASSERT_TRUE(rig.commands.try_send(c));
    step();
    EXPECT_EQ(manager.damaged_records(), damaged + 1);
    EXPECT_EQ(manager.refused_commands(), refused);
    for (std::size_t j = 0; j < kJointCount; ++j) {
      EXPECT_EQ(manager.statuses()[j].state, before[j].state) << kJoints[j].name;
      EXPECT_EQ(manager.statuses()[j].mode, before[j].mode) << kJoints[j].name;
      EXPECT_EQ(manager.statuses()[j].drive_enabled, before[j].drive_enabled) << kJoints[j].name;
    }
    EXPECT_EQ(manager.lost_joints(), 0u);
  }
};

template <typename Field>
void set_byte(Field& field, std::uint8_t byte) {
  static_assert(sizeof(Field) == 1, "an enum of one byte");
  std::memcpy(&field, &byte, 1);  // as a stray write leaves it in the segment
}

TEST_F(JointManagerDamagedRecords, ACommandNamingAJointBeyondTheRobotIsRefusedWholeAndCounted) {
  ready_robot();
  expect_refused_whole(JointCommand{joint_bit(kElbow) | (JointMask{1} << 31), JointInput::enable, ControlMode::none,
                                    JointCommandKind::dfa_input});
  // The next whole command is applied as before.
  rig.command(joint_bit(kElbow), JointInput::enable);
  step();
  EXPECT_EQ(manager.statuses()[kElbow].state, JointState::enabled);
  EXPECT_EQ(manager.damaged_records(), 1u);
}

TEST_F(JointManagerDamagedRecords, ACommandOfAnUnknownKindIsNotTakenAsAStateMachineInput) {
  ready_robot();
  JointCommand c{joint_bit(kElbow), JointInput::enable, ControlMode::none, JointCommandKind::dfa_input};
  set_byte(c.kind, 0x7F);
  expect_refused_whole(c);  // read as it was, the elbow was enabled
}

TEST_F(JointManagerDamagedRecords, ACommandOfAnUnknownInputIsRefusedAsDamageNotAsAStateMachineRefusal) {
  ready_robot();
  JointCommand c{kAllJoints, JointInput::enable, ControlMode::none, JointCommandKind::dfa_input};
  set_byte(c.input, 200);
  expect_refused_whole(c);
}

TEST_F(JointManagerDamagedRecords, ACommandOfAnUnknownModeNeverBecomesAJointsRequestedMode) {
  ready_robot();
  JointCommand c{joint_bit(kElbow), JointInput::select_mode, ControlMode::none, JointCommandKind::dfa_input};
  set_byte(c.mode, 0x55);
  expect_refused_whole(c);  // read as it was, an operator's bad_mode refusal
  c.input = JointInput::set_reference;
  expect_refused_whole(c);  // read as it was, 0x55 became the elbow's requested mode
}

TEST_F(JointManagerDamagedRecords, ACommandWhoseStepIsNotWithinItsStepsIsRefused) {
  ready_robot();
  JointCommand c{joint_bit(kElbow), JointInput::enable, ControlMode::none, JointCommandKind::dfa_input};
  c.request = 7;
  c.all_or_nothing = true;
  c.steps = 200;  // beyond kMaxRequestSteps: read as it was, applied as a lone command
  expect_refused_whole(c);
  c.steps = 0;
  expect_refused_whole(c);
  c.steps = 2;
  c.step = 2;
  expect_refused_whole(c);
}

TEST_F(JointManagerDamagedRecords, AReportNamingAJointBeyondTheRobotRecordsNoLoss) {
  ready_robot();
  LostJointsReport report;
  report.lost = joint_bit(kElbow) | (JointMask{1} << 30);
  report.cycle = 5;
  report.detected_at = now;
  ASSERT_TRUE(rig.reports.try_send(report));
  step();
  EXPECT_EQ(manager.lost_joints(), 0u);
  EXPECT_EQ(manager.statuses()[kElbow].state, JointState::ready);
  EXPECT_EQ(manager.damaged_records(), 1u);
  EXPECT_EQ(rig.notices.size(), 0u);  // no answer: nothing was recorded
  // A whole report is handled as before.
  report.lost = joint_bit(kElbow);
  ASSERT_TRUE(rig.reports.try_send(report));
  step();
  EXPECT_EQ(manager.lost_joints(), joint_bit(kElbow));
}

}  // namespace
}  // namespace rescue::app
