// Issue 12: a run whose supervisor is SIGKILLed in OP leaves its shared-memory segment behind; its
// task processes do not outlive it (the EtherCAT handler disables the drives and ends, the others are
// killed); the next run with the same segment finds the creator dead, replaces the segment with a log
// line naming the dead pid, and runs normally.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

#include "hal/shm/shared_memory.hpp"
#include "tests/support/background_run.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

using std::chrono::milliseconds;

bool gone_within(pid_t pid, milliseconds limit) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < until) {
    if (::kill(pid, 0) != 0) return true;
    std::this_thread::sleep_for(milliseconds(10));
  }
  return ::kill(pid, 0) != 0;
}

TEST(StaleSegment, TheNextRunReplacesTheSegmentOfAKilledRun) {
  testing::TempStateDir dir;
  const std::string segment = "/rescue-test-stale-" + std::to_string(::getpid());
  pid_t killed = 0;
  {
    test::BackgroundRun first({"run", "--duration", "60", "--initialize", "--state-dir", dir.path, "--segment", segment},
                              dir.path + "/first.log");
    ASSERT_TRUE(first.wait_for("operator: initialize: accepted", milliseconds(30000))) << first.output();
    const pid_t handler = first.pid_on_line("supervisor: started ethercat-handler");
    const pid_t manager = first.pid_on_line("supervisor: started joint-manager");
    ASSERT_GT(handler, 0);
    ASSERT_GT(manager, 0);
    killed = first.pid();
    ASSERT_EQ(::kill(killed, SIGKILL), 0);
    EXPECT_EQ(first.wait_exit(), -SIGKILL);
    EXPECT_TRUE(gone_within(manager, milliseconds(2000))) << "the joint manager outlived its supervisor";
    EXPECT_TRUE(gone_within(handler, milliseconds(5000))) << "the EtherCAT handler outlived its supervisor";
    EXPECT_TRUE(first.wait_for("every reachable drive disabled", milliseconds(1000))) << first.output();
  }
  ASSERT_TRUE(hal::SharedMemory::open_existing(segment.c_str()).ok()) << "the killed run left its segment";
  test::BackgroundRun second({"run", "--duration", "0.3", "--state-dir", dir.path, "--segment", segment},
                             dir.path + "/second.log");
  const int status = second.wait_exit();
  const std::string out = second.output();
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("replaced stale shared-memory segment " + segment + " (its creator is dead, creator pid " +
                     std::to_string(killed) + ")"),
            std::string::npos)
      << out;
  EXPECT_EQ(hal::SharedMemory::open_existing(segment.c_str()).error().code, Errc::not_found) << "not removed at the end";
}

}  // namespace
}  // namespace rescue::app
