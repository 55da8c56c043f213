// `rescue-motion run --nic raw:` on a veth pair with nothing at the other end (no simulator, no
// segment): the bring-up is never silent. It says every second that no frame has come back yet, how
// many BRDs it sent and when it gives up, and follows --first-contact-limit: exit status 1 with the
// reason after the limit (docs/firmware.md), or, with 0, keeps trying until SIGTERM or SIGINT, which
// stop it cleanly (exit 0) with one line saying it was during bring-up (issue 11 item 5: the bring-up
// lasts until stopped here, so the signal cannot come after it).
#include <gtest/gtest.h>

#include <signal.h>
#include <time.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"
#include "tests/support/netns_veth.hpp"

namespace rescue::app {
namespace {

using RunWithoutSegment = rescue::testing::NetnsTest;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

std::vector<std::string> run_argv(const std::string& state, const char* limit) {
  return {std::string(RESCUE_BINARY_DIR) + "/rescue-motion", "run", "--nic",
          std::string("raw:") + rescue::testing::VethPair::kMasterInterface, "--state-dir", state, "--first-contact-limit",
          limit};
}

constexpr double kDefaultLimitS = 5.0;  // --first-contact-limit's default
constexpr double kPatienceS = 120.0;    // the test's own bound on a starved host

// The longest wait a "waiting for first contact: ... (N BRDs in S s)" line reports (0 when none).
double longest_reported_wait(const std::string& text) {
  double longest = 0.0;
  const std::string marker = " BRDs in ";
  for (std::size_t at = text.find(marker); at != std::string::npos; at = text.find(marker, at + 1)) {
    longest = std::max(longest, std::strtod(text.c_str() + at + marker.size(), nullptr));
  }
  return longest;
}

double now_s() {
  timespec t{};
  ::clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

TEST_F(RunWithoutSegment, ReportsItsWaitEverySecondAndGivesUpAtItsLimit) {
  char dir[] = "/tmp/rm-first-contact-XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  rescue::testing::ChildProcess run;
  const double started = now_s();
  ASSERT_TRUE(run.start(run_argv(dir, "3.5"), veth_->master_ns()));
  const int status = run.wait_exit();
  const double took = now_s() - started;
  EXPECT_EQ(status, 1) << run.output();
  EXPECT_GE(count(run.output(), "waiting for first contact: no EtherCAT frame came back yet"), 3u) << run.output();
  EXPECT_NE(run.output().find("giving up after 3.5 s"), std::string::npos) << run.output();
  EXPECT_NE(run.output().find("bring-up failed at count: no EtherCAT frame came back"), std::string::npos) << run.output();
  EXPECT_GE(took, 3.5);
  (void)std::system((std::string("rm -rf ") + dir).c_str());
}

TEST_F(RunWithoutSegment, KeepsTryingWithoutALimitUntilStopped) {
  char dir[] = "/tmp/rm-first-contact-XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  rescue::testing::ChildProcess run;
  ASSERT_TRUE(run.start(run_argv(dir, "0"), veth_->master_ns()));
  // Still waiting, and saying so, after twice the default limit (5 s) by the run's own account:
  // how long that takes on the test's clock depends on the CPU the host leaves it (under the load
  // stage's stress-ng it once printed 5 lines in 10.5 s), so the wait is judged by what it reports.
  const double deadline = now_s() + kPatienceS;
  while (longest_reported_wait(run.output()) < 2 * kDefaultLimitS && now_s() < deadline) {
    (void)run.wait_for_output("never printed", 500);
  }
  EXPECT_GE(longest_reported_wait(run.output()), 2 * kDefaultLimitS) << run.output();
  EXPECT_GE(count(run.output(), "trying until stopped"), 2u) << run.output();
  EXPECT_EQ(run.output().find("bring-up failed"), std::string::npos) << run.output();
  EXPECT_EQ(run.stop(SIGTERM), 0) << run.output();
  EXPECT_NE(run.output().find("stopped by signal 15 during bring-up"), std::string::npos) << run.output();
  (void)std::system((std::string("rm -rf ") + dir).c_str());
}

TEST_F(RunWithoutSegment, SigintDuringBringUpStopsCleanlyAndSaysWhere) {
  char dir[] = "/tmp/rm-first-contact-XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  rescue::testing::ChildProcess run;
  ASSERT_TRUE(run.start(run_argv(dir, "0"), veth_->master_ns()));
  ASSERT_TRUE(run.wait_for_output("bringing the EtherCAT network up", 5000)) << run.output();
  EXPECT_EQ(run.stop(SIGINT), 0) << "exit 0, not killed by the signal: " << run.output();
  EXPECT_NE(run.output().find("stopped by signal 2 during bring-up"), std::string::npos) << run.output();
  (void)std::system((std::string("rm -rf ") + dir).c_str());
}

}  // namespace
}  // namespace rescue::app
