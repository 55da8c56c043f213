// Periods without a cycle are reported, not silently missing from the count (issue 11, item 7: a
// 2 s run made 1964-1996 cycles and said nothing). The run is stopped (SIGSTOP) for 100 ms in OP, as
// a stalled host would: the summary's late periods then hold at least the ~100 periods that got no
// cycle ("N not run"), and cycles + not run cover the run's periods. A stall only adds periods, so
// host jitter cannot make this test fail; only a missing count can.
#include <gtest/gtest.h>

#include <cinttypes>
#include <cstdio>
#include <string>

#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

TEST(RunCommand, AStallInOpIsReportedAsLatePeriodsNotRun) {
  testing::TempStateDir dir;
  const std::string log = dir.path + "/run.log";
  // Start, wait for OP (at most 20 s), stop the process for 100 ms, let it finish. --threads: the
  // EtherCAT handler is a thread of the one process SIGSTOP stops (by default it is a child process).
  const std::string script =
      "'" + kBinary + "' run --threads --duration 1 --state-dir '" + dir.path + "' >'" + log + "' 2>&1 & pid=$!; " +
      "for i in $(seq 200); do grep -q 'network in OP' '" + log + "' && break; sleep 0.1; done; " +
      "sleep 0.2; kill -STOP $pid; sleep 0.1; kill -CONT $pid; wait $pid; echo status=$?; cat '" + log + "'";
  const test::CommandOutput out = test::run_command(script);
  ASSERT_NE(out.out.find("status=0"), std::string::npos) << out.out;
  const std::size_t summary = out.out.find(" cycles; healthy joints missed");
  ASSERT_NE(summary, std::string::npos) << out.out;
  const std::size_t at = out.out.rfind("rescue-motion run: ", summary);
  ASSERT_NE(at, std::string::npos) << out.out;
  std::uint64_t cycles = 0;
  std::uint64_t missed = 0;
  std::uint64_t frames = 0;
  std::uint64_t late = 0;
  std::uint64_t not_run = 0;
  ASSERT_EQ(std::sscanf(out.out.c_str() + at,
                        "rescue-motion run: %" SCNu64 " cycles; healthy joints missed %" SCNu64
                        " cycles; frames late or lost: %" SCNu64 "; late periods: %" SCNu64 " (%" SCNu64 " not run)",
                        &cycles, &missed, &frames, &late, &not_run),
            5)
      << out.out.substr(at);
  EXPECT_GE(not_run, 80U) << out.out.substr(at);  // 100 ms stopped at 1 ms: ~100 periods had no cycle
  EXPECT_GE(late, not_run);
  EXPECT_GE(cycles + not_run, 1000U) << "a 1 s run in OP has at least 1000 periods";
}

}  // namespace
}  // namespace rescue::app
