// `rescue-motion bench latency` runs the EtherCAT handler's real loop (wake_at, then the handler's
// cycle on the in-process simulated robot) with `run`'s real-time set-up, interleaved period by
// period with a reference loop (cyclictest's method, a second thread on the same CPU and priority),
// then cyclictest with the same priority, CPU and PM QoS choice, and prints the three loops' figures,
// the ratios and 0 heap allocations in the loop; --no-pm-qos runs all without the request. No timing
// is asserted. Where the kernel refuses SCHED_FIFO (no CAP_SYS_NICE, a cgroup without real-time
// runtime), cyclictest cannot run at the handler's priority: the bench still prints its own loop's
// and the interleaved reference's figures, says why there is no ratio to cyclictest, and exits 1.
#include <gtest/gtest.h>

#include "core/base/sanitizers.hpp"

#include <cstdlib>
#include <string>

#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

bool have_cyclictest() { return std::system("command -v cyclictest >/dev/null 2>&1") == 0; }

// The kernel refused the handler's SCHED_FIFO (the bench's real-time set-up says so).
bool fifo_refused(const std::string& out) { return contains(out, "\nrt: SCHED_FIFO priority 80: refused"); }

// Without SCHED_FIFO: exit status 1, the reason, and no ratio to cyclictest.
void expect_no_cyclictest_ratio(const test::CommandOutput& out) {
  EXPECT_EQ(out.exit_status, 1) << out.out;
  EXPECT_TRUE(contains(out.out, "cyclictest did not run: no ratio")) << out.out;
  EXPECT_FALSE(contains(out.out, "\nratio_p50: ")) << out.out;
}

TEST(BenchLatency, RunsTheHandlersLoopAndCyclictestWithThePmQosRequest) {
  // A sanitizer build refuses SCHED_FIFO (docs/build.md): latency is measured on optimised builds.
  if (kSanitizerSpinsBySchedYield) GTEST_SKIP() << "a sanitizer build refuses SCHED_FIFO";
  if (!have_cyclictest()) GTEST_SKIP() << "cyclictest not installed (rt-tests, toolchain/setup.sh)";
  const test::CommandOutput out = test::run_command(kBinary + " bench latency --periods 200 2>&1");
  if (fifo_refused(out.out)) {
    expect_no_cyclictest_ratio(out);
  } else {
    ASSERT_EQ(out.exit_status, 0) << out.out;
    for (const char* line : {"\ncyclictest_latency_p50: ", "\ncyclictest_latency_p99: ", "\nratio_p50: ", "\nratio_p99: "}) {
      EXPECT_TRUE(contains(out.out, line)) << line << "\n" << out.out;
    }
  }
  for (const char* line : {"\nloop: the EtherCAT handler's", "\npm_qos: held at 0 us by both loops",
                           "\nheap_allocations_in_loop: 0 allocations\n", "\nours_periods: 200 periods\n",
                           "\nours_latency_p50: ", "\nours_latency_p99: ", "\nreference: cyclictest's loop",
                           "\nreference_latency_p50: ", "\nreference_latency_p99: ", "\nreference_skipped: ",
                           "\nratio_interleaved_p50: ", "\nratio_interleaved_p99: ", "\nrt: timer slack 1 ns: ",
                           "\nrt: CPU wake-up latency (PM QoS, /dev/cpu_dma_latency) 0 us: "}) {
    EXPECT_TRUE(contains(out.out, line)) << line << "\n" << out.out;
  }
  // The reference ran beside ours: one release per period of ours, skipped only inside our cycle
  // (about 100 us of a 1000 us period), so most of the 200 are recorded.
  const std::size_t at = out.out.find("\nreference_periods: ");
  ASSERT_NE(at, std::string::npos) << out.out;
  EXPECT_GE(std::atoi(out.out.c_str() + at + 20), 100) << out.out;
}

TEST(BenchLatency, NoPmQosLeavesTheRequestToNeitherLoop) {
  // A sanitizer build refuses SCHED_FIFO (docs/build.md): latency is measured on optimised builds.
  if (kSanitizerSpinsBySchedYield) GTEST_SKIP() << "a sanitizer build refuses SCHED_FIFO";
  if (!have_cyclictest()) GTEST_SKIP() << "cyclictest not installed (rt-tests, toolchain/setup.sh)";
  const test::CommandOutput out = test::run_command(kBinary + " bench latency --periods 200 --no-pm-qos 2>&1");
  if (fifo_refused(out.out)) {
    expect_no_cyclictest_ratio(out);
  } else {
    ASSERT_EQ(out.exit_status, 0) << out.out;
    EXPECT_TRUE(contains(out.out, "\nratio_p50: ")) << out.out;
  }
  EXPECT_TRUE(contains(out.out, "\npm_qos: not held by either loop")) << out.out;
  EXPECT_FALSE(contains(out.out, "/dev/cpu_dma_latency) 0 us:")) << "the request was not made\n" << out.out;
  EXPECT_TRUE(contains(out.out, "\nratio_interleaved_p50: ")) << out.out;
}

}  // namespace
}  // namespace rescue::app
