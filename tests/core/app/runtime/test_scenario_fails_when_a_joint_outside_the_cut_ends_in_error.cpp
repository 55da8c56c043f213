// A scenario's verdict looked at the cut, the missed cycles and the rescue's residuals, but not at
// the joints outside the cut: `run --scenario rescue` printed "passed" and exited 0 with both elbows
// in Error after a following error (0x8611). A joint outside the cut that ends in Error now fails
// the scenario; the lost joints and those restored in Error from the file are excused.
#include <gtest/gtest.h>

#include "core/app/runtime/run_report.hpp"

namespace rescue::app::runner {
namespace {

RobotJointStatus all_enabled() {
  RobotJointStatus status{};
  for (PublishedJointStatus& joint : status) joint.state = fsm::JointState::enabled;
  return status;
}

TEST(ScenarioVerdict, EveryJointEnabledHasNoneInError) {
  EXPECT_EQ(joints_ended_in_error(all_enabled(), 0), 0U);
}

TEST(ScenarioVerdict, AHealthyJointInErrorIsFound) {
  RobotJointStatus status = all_enabled();
  status[3].state = fsm::JointState::error;
  status[3].fault = FaultReason::drive_fault;
  status[9].state = fsm::JointState::error;
  EXPECT_EQ(joints_ended_in_error(status, 0), joint_bit(3) | joint_bit(9));
}

TEST(ScenarioVerdict, LostAndRestoredJointsAreExcused) {
  RobotJointStatus status = all_enabled();
  status[3].state = fsm::JointState::error;
  status[9].state = fsm::JointState::error;
  EXPECT_EQ(joints_ended_in_error(status, joint_bit(3)), joint_bit(9));
  EXPECT_EQ(joints_ended_in_error(status, joint_bit(3) | joint_bit(9)), 0U);
}

TEST(ScenarioVerdict, IdleReadyAndConfiguredAreNotErrors) {
  RobotJointStatus status = all_enabled();
  status[0].state = fsm::JointState::idle;
  status[1].state = fsm::JointState::configured;
  status[2].state = fsm::JointState::ready;
  EXPECT_EQ(joints_ended_in_error(status, 0), 0U);
}

}  // namespace
}  // namespace rescue::app::runner
