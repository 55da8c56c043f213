// Issue 12: per task process, heap allocations and page faults after init are reported at the end of
// `run` as `key: value` lines; every real-time process (EtherCAT handler, joint manager, the two RC
// tasks: SCHED_FIFO in the task table) reports 0 of both over a run in which the robot moves the whole
// time: the rescue RC task owning (its IK path, the handler's motion intake) and the teleop RC task
// owning (joint-space hand motion), in turns. Page faults are only promised where the memory can be
// locked (mlockall: root or RLIMIT_MEMLOCK), as on the robot.
//
// The run lasts RESCUE_LONG_RUN_SECONDS seconds (default 6: the CI form, one turn of each owner); the
// full form (docs/tasks.md "Long run") sets it to 600.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using std::chrono::milliseconds;
using testing::OperatorRun;

// AddressSanitizer maps its shadow memory lazily: every first touch of a shadow page is a page fault
// that the real firmware does not have, so the page-fault promise is checked in uninstrumented builds.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitizerShadowMemory = true;
#else
constexpr bool kSanitizerShadowMemory = false;
#endif

constexpr const char* kRealTimeProcesses[] = {"ethercat-handler", "joint-manager", "rc-rescue", "rc-teleop"};

bool can_lock_memory() {
  rlimit limit{};
  return ::geteuid() == 0 || (::getrlimit(RLIMIT_MEMLOCK, &limit) == 0 && limit.rlim_cur == RLIM_INFINITY);
}

// RESCUE_LONG_RUN_SECONDS (whole seconds, 1..86400), else 6.
int long_run_seconds() {
  const char* text = std::getenv("RESCUE_LONG_RUN_SECONDS");
  const int seconds = text != nullptr ? std::atoi(text) : 0;
  return seconds >= 1 && seconds <= 86400 ? seconds : 6;
}

// The `key: value` line's value after `key` ("" when absent).
std::string value_of(const std::string& out, const std::string& key) {
  const std::size_t at = out.find("\n" + key);
  if (at == std::string::npos) return std::string();
  const std::size_t begin = at + 1 + key.size();
  return out.substr(begin, out.find('\n', begin) - begin);
}

// The owner of `joint` in `ctl --json status` ("" when absent).
std::string owner_of(const std::string& json, const std::string& joint) {
  const std::size_t at = json.find("\"name\":\"" + joint + "\"");
  if (at == std::string::npos) return std::string();
  const std::size_t f = json.find("\"owner\":", at);
  if (f == std::string::npos) return std::string();
  return json.substr(f + 8, json.find_first_of(",}", f + 8) - (f + 8));
}

// `ctl ARGS` accepted, tried up to 3 times 100 ms apart; a command still refused is counted in
// `refused` with its answers kept in `answers`. On a shared host an RC task can be starved past the
// 100 ms after which the parser answers "no RC task running": host load, not what this test is about;
// the motion itself is checked from the run's figures.
void command(const OperatorRun& run, const std::vector<std::string>& args, int* refused, std::string* answers) {
  for (int attempt = 0; attempt < 3; ++attempt) {
    const testing::CommandResult r = run.ctl(args);
    if (r.status == 0) return;
    if (attempt == 2) *answers += r.out;
    std::this_thread::sleep_for(milliseconds(100));
  }
  ++*refused;
}

TEST(TaskProcessHealth, RealTimeProcessesAllocateNothingAndFaultNoPageAfterInitWhileTheRobotMoves) {
  const int seconds = long_run_seconds();
  OperatorRun run(std::to_string(seconds + 120).c_str());
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  ASSERT_EQ(run.ctl({"init"}).status, 0) << run.output();
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  // Turns of 5 s while the run lasts: the rescue task owns 3 s (approach and its IK motion), then the
  // teleop task closes and opens the left hand, 1 s each.
  int turns = 0;
  int refused = 0;
  std::string answers;
  int rescue_seen = 0;  // turns whose sample showed l_elbow driven by RC task 0
  int teleop_seen = 0;  // turns whose sample showed l_hand driven by RC task 1
  while (std::chrono::steady_clock::now() < end) {
    command(run, {"owner", "0"}, &refused, &answers);
    std::this_thread::sleep_for(milliseconds(2900));
    if (owner_of(run.ctl({"--json", "status"}).out, "l_elbow") == "0") ++rescue_seen;
    command(run, {"owner", "1"}, &refused, &answers);
    command(run, {"hand", "left", "close", "--task", "1"}, &refused, &answers);
    std::this_thread::sleep_for(milliseconds(1000));
    command(run, {"hand", "left", "open", "--task", "1"}, &refused, &answers);
    std::this_thread::sleep_for(milliseconds(900));
    if (owner_of(run.ctl({"--json", "status"}).out, "l_hand") == "1") ++teleop_seen;
    ++turns;
  }
  ASSERT_EQ(run.stop(), 0) << run.output();
  const std::string out = run.output();

  for (const char* task : kRealTimeProcesses) {
    EXPECT_NE(out.find(std::string(task) + " heap allocations after init: 0\n"), std::string::npos) << task << "\n" << out;
    if (can_lock_memory() && !kSanitizerShadowMemory) {
      EXPECT_NE(out.find(std::string(task) + " page faults after init: 0\n"), std::string::npos) << task << "\n" << out;
    }
    EXPECT_EQ(value_of(out, std::string(task) + " restarts: "), "0") << task << "\n" << out;
  }
  // The other processes report too (figures not promised: they are not real-time).
  EXPECT_NE(out.find("message-parser heap allocations after init: "), std::string::npos) << out;
  // The robot moved: both RC tasks drove joints, and the owners' references drove them nearly always.
  EXPECT_GT(rescue_seen, 0) << out;
  EXPECT_GT(teleop_seen, 0) << out;
  const std::string used = value_of(out, "owner_references_used: ");
  EXPECT_FALSE(used.empty()) << out;
  EXPECT_GT(std::atoll(used.c_str()), 500LL * seconds) << out;  // of the ~1000 handler periods a second
  // Ownership changed while the hand moved (docs/operator.md's example, over and over): every
  // reference sent kept every limit (issue 33: the hand was stopped at 100x its acceleration limit),
  // and no figure is a sentinel.
  EXPECT_EQ(value_of(out, "joint_limits: "), "within") << out;
  EXPECT_EQ(value_of(out, "rescue_joint_limits: "), "within") << out;
  EXPECT_EQ(out.find("1000000000"), std::string::npos) << out;

  std::printf("long run: %d s (RESCUE_LONG_RUN_SECONDS), %d turns, owner seen driving: rescue %d, teleop %d; %s\n",
              seconds, turns, rescue_seen, teleop_seen, can_lock_memory() && !kSanitizerShadowMemory ? "page faults asserted" : "page faults printed");
  for (const char* task : kRealTimeProcesses) {
    std::printf("long run: %s heap allocations after init %s, page faults after init %s, periods %s, missed %s\n", task,
                value_of(out, std::string(task) + " heap allocations after init: ").c_str(),
                value_of(out, std::string(task) + " page faults after init: ").c_str(),
                value_of(out, std::string(task) + " periods: ").c_str(),
                value_of(out, std::string(task) + " periods missed: ").c_str());
  }
  if (refused > 0) std::printf("long run: %d ctl commands refused 3 times (host load), the last answers:\n%s", refused, answers.c_str());
  std::printf("long run: owner_periods %s, owner_references_used %s, owner_misses %s, owner_releases %s\n",
              value_of(out, "owner_periods: ").c_str(), used.c_str(), value_of(out, "owner_misses: ").c_str(),
              value_of(out, "owner_releases: ").c_str());
}

}  // namespace
}  // namespace rescue::app
