// The firmware's tasks as `run` starts them (EtherCAT handler and joint manager threads, the logger
// in the main thread) on the simulated robot for half a second with the robot initialized. Labelled
// `concurrency`: under the tsan preset ThreadSanitizer checks every access the threads share
// (seqlocks, SPSC queues, run-state atomics) while the program runs as it does for the robot team.
#include <gtest/gtest.h>

#include "core/app/runtime/firmware.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

TEST(FirmwareTasks, RunHalfASecondOnTheSimulatedRobotAndStopCleanly) {
  testing::TempStateDir dir;
  FirmwareOptions options;
  options.state_dir = dir.path.c_str();
  options.duration = hal::kNsPerSec / 2;
  options.initialize = true;
  options.threads = true;  // ThreadSanitizer watches threads; the processes mode shares the same memory
  EXPECT_EQ(run_firmware(options), 0);
}

}  // namespace
}  // namespace rescue::app
