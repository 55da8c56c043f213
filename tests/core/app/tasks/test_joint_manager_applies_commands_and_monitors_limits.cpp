// The joint manager's DFAs driven by joint commands (the message parser's joint handle queue), and its
// limit monitoring: a violation or a drive fault puts that joint, and only it, in Error with the reason
// recorded; reset is refused until the fault is gone.
#include <gtest/gtest.h>

#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

using fsm::JointInput;
using fsm::JointState;

const std::size_t kElbow = joint_index_by_name("l_elbow");
const std::size_t kNeck = joint_index_by_name("neck_pan");

class JointManagerCommands : public testing::JointManagerFixture {
 protected:
  // The message parser's "initialize robot": select mode, set reference to the current position, enable.
  void initialize_robot() {
    select_csp_at_current_position();
    rig.command(kAllJoints, JointInput::enable);
    step();
  }
  JointState state(std::size_t j) const { return manager.statuses()[j].state; }
};

TEST_F(JointManagerCommands, InitializeRobotEnablesEveryJointWithReferenceAtCurrentPosition) {
  initialize_robot();
  EXPECT_EQ(manager.summary().condition, fsm::RobotCondition::enabled);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointStatus& s = manager.statuses()[j];
    EXPECT_EQ(s.state, JointState::enabled) << kJoints[j].name;
    EXPECT_TRUE(s.drive_enabled);
    EXPECT_EQ(s.mode, ControlMode::cyclic_position);
    EXPECT_EQ(s.reference_position_rad, rig.samples.robot[j].position_rad);
  }
  EXPECT_EQ(manager.refused_commands(), 0u);
}

// An owner moved the hand while it was Enabled; the operator disables and enables it again. Its
// reference follows where it is at each step, so enabling moves nothing (a reference left at the
// initialise-time position made the drive jump back and fault with a following error).
TEST_F(JointManagerCommands, DisableThenEnableKeepsTheJointWhereItIs) {
  const std::size_t hand = joint_index_by_name("l_hand");
  initialize_robot();
  rig.samples.robot[hand].position_rad += 0.5;  // moved by the owner's references
  step();
  rig.command(joint_bit(hand), JointInput::disable);
  step();
  EXPECT_EQ(state(hand), JointState::ready);
  EXPECT_EQ(manager.statuses()[hand].reference_position_rad, rig.samples.robot[hand].position_rad);
  rig.samples.robot[hand].position_rad -= 0.05;  // pushed while the drive was off
  step();
  rig.command(joint_bit(hand), JointInput::enable);
  step();
  EXPECT_EQ(state(hand), JointState::enabled);
  EXPECT_EQ(manager.statuses()[hand].reference_position_rad, rig.samples.robot[hand].position_rad);
}

TEST_F(JointManagerCommands, RefusedCommandsAreCountedAndLoggedNeverIgnored) {
  rig.command(joint_bit(kNeck), JointInput::enable);  // Idle + enable: not in the table
  step();
  EXPECT_EQ(state(kNeck), JointState::idle);
  EXPECT_EQ(manager.refused_commands(), 1u);
  EXPECT_TRUE(rig.log.contains("neck_pan: enable refused in Idle (transition not in table)"));

  rig.command(joint_bit(kNeck), JointInput::select_mode, ControlMode::none);
  step();
  EXPECT_EQ(manager.refused_commands(), 2u);
  EXPECT_TRUE(rig.log.contains("select_mode needs CSP, CSV or CST"));

  rig.samples.robot[kNeck].reachable = false;
  rig.command(joint_bit(kNeck), JointInput::select_mode, ControlMode::cyclic_position);
  step();
  EXPECT_EQ(state(kNeck), JointState::idle);
  EXPECT_TRUE(rig.log.contains("neck_pan: select_mode refused in Idle (joint not reachable)"));
}

TEST_F(JointManagerCommands, VelocityOverLimitPutsOnlyThatJointInErrorWithTheReason) {
  initialize_robot();
  rig.samples.robot[kElbow].velocity_rad_s = 2.5;  // limit 2.0
  step();
  const JointStatus& elbow = manager.statuses()[kElbow];
  EXPECT_EQ(elbow.state, JointState::error);
  EXPECT_FALSE(elbow.drive_enabled);
  EXPECT_EQ(elbow.fault.reason, FaultReason::velocity_limit);
  EXPECT_DOUBLE_EQ(elbow.fault.value, 2.5);
  EXPECT_DOUBLE_EQ(elbow.fault.limit, 2.0);
  EXPECT_TRUE(rig.log.contains("l_elbow: velocity above limit (value 2.5, limit 2)"));
  EXPECT_TRUE(rig.log.contains("l_elbow: Enabled --fault--> Error"));
  EXPECT_EQ(manager.summary().condition, fsm::RobotCondition::degraded);
  EXPECT_EQ(manager.summary().usable, kAllJoints & ~joint_bit(kElbow));
}

TEST_F(JointManagerCommands, ResetIsRefusedWhileTheFaultPersistsThenAccepted) {
  initialize_robot();
  rig.samples.robot[kElbow].torque_nm = -90.0;  // limit 80
  step();
  ASSERT_EQ(state(kElbow), JointState::error);
  rig.command(joint_bit(kElbow), JointInput::reset);
  step();
  EXPECT_EQ(state(kElbow), JointState::error);
  EXPECT_TRUE(rig.log.contains("l_elbow: reset refused in Error (guard refused transition)"));
  EXPECT_EQ(manager.statuses()[kElbow].fault.reason, FaultReason::torque_limit);  // still says why

  rig.samples.robot[kElbow].torque_nm = 10.0;
  rig.command(joint_bit(kElbow), JointInput::reset);
  step();
  EXPECT_EQ(state(kElbow), JointState::idle);
  EXPECT_EQ(manager.statuses()[kElbow].fault.reason, FaultReason::none);
}

TEST_F(JointManagerCommands, OutOfLimitReferenceMattersOnlyWhileEnabled) {
  rig.command(joint_bit(kElbow), JointInput::select_mode, ControlMode::cyclic_position);
  rig.command(joint_bit(kElbow), JointInput::set_reference);
  step();
  rig.samples.robot[kElbow].position_ref_rad = 2.7;  // above 2.5, but nothing is sent in Ready
  step();
  EXPECT_EQ(state(kElbow), JointState::ready);
  rig.command(joint_bit(kElbow), JointInput::enable);
  step();
  EXPECT_EQ(state(kElbow), JointState::error);
  EXPECT_EQ(manager.statuses()[kElbow].fault.reason, FaultReason::position_reference_limit);
}

TEST_F(JointManagerCommands, DriveFaultIsAnErrorWithItsCode) {
  initialize_robot();
  rig.samples.robot[kNeck].drive_fault = true;
  rig.samples.robot[kNeck].drive_error_code = 0x2310;
  step();
  EXPECT_EQ(state(kNeck), JointState::error);
  EXPECT_EQ(manager.statuses()[kNeck].fault.reason, FaultReason::drive_fault);
  EXPECT_DOUBLE_EQ(manager.statuses()[kNeck].fault.value, 0x2310);
}

TEST_F(JointManagerCommands, StaleValuesOfAnUnreachableJointAreNotJudged) {
  initialize_robot();
  rig.samples.robot[kElbow].reachable = false;
  rig.samples.robot[kElbow].velocity_rad_s = 99.0;
  step();
  EXPECT_EQ(state(kElbow), JointState::enabled);  // its loss comes from the handler's report
}

TEST_F(JointManagerCommands, AtMostABoundedNumberOfCommandsPerStep) {
  for (int i = 0; i < 40; ++i) rig.command(joint_bit(kNeck), JointInput::disable);  // each refused in Idle
  step();
  EXPECT_EQ(manager.refused_commands(), JointManager::kMaxCommandsPerStep);
  EXPECT_EQ(rig.commands.size(), 40 - JointManager::kMaxCommandsPerStep);
  step();
  EXPECT_EQ(manager.refused_commands(), 40u);
}

}  // namespace
}  // namespace rescue::app
