// Issue 11: a run whose robot ended in error (every joint in Error) exited 0. The exit status of a
// run that stopped in order follows the robot's condition: non-zero for error, 0 otherwise.
#include <gtest/gtest.h>

#include "core/app/runtime/firmware.hpp"

namespace rescue::app {
namespace {

TEST(RunExitStatus, RobotInErrorIsNeverSuccess) {
  EXPECT_EQ(exit_status_for(fsm::RobotCondition::error), kExitRobotError);
  EXPECT_NE(kExitRobotError, 0);
  EXPECT_NE(kExitRobotError, 1) << "distinct from a failed start or a failed scenario";
}

TEST(RunExitStatus, UsableRobotIsSuccess) {
  for (const fsm::RobotCondition c : {fsm::RobotCondition::idle, fsm::RobotCondition::configured, fsm::RobotCondition::ready,
                                      fsm::RobotCondition::enabled, fsm::RobotCondition::degraded}) {
    EXPECT_EQ(exit_status_for(c), 0) << fsm::to_string(c);
  }
}

}  // namespace
}  // namespace rescue::app
