// `bench master --scheduling normal` runs our master as SOEM's test program runs (default scheduler,
// any CPU, no receive spin), so the side-by-side comparison (docs/master.md) can tell the master's
// receive path from its real-time placement; the default stays the EtherCAT task's SCHED_FIFO 80 on
// CPU 1, and anything else is refused with the accepted values.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(BenchMasterScheduling, NormalSkipsPinningAndPriorityAndSaysSo) {
  const test::CommandOutput out = test::run_command(kBinary + " bench master --scheduling normal --cycles 100 2>&1");
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "scheduling: normal (default scheduler, any CPU)")) << out.out;
  EXPECT_TRUE(contains(out.out, "receive_wait: sleep, spin at most 0 us")) << out.out;
  EXPECT_TRUE(contains(out.out, "rt: CPU affinity: skipped")) << out.out;
  EXPECT_TRUE(contains(out.out, "rt: SCHED_FIFO priority: skipped")) << out.out;
  EXPECT_TRUE(contains(out.out, "cycles_all_joints_valid: 100 cycles")) << out.out;
  // Frames that missed their deadline, those that came back later and the oldest one's age (none on
  // the in-process simulated robot, whose frames are never late).
  EXPECT_TRUE(contains(out.out, "cyclic_frames_timed_out: 0 frames (0 came back after their deadline, 0 of them within 2 ms "
                                "of their sending, the latest 0.0 us after its sending, whole run)")) << out.out;
  // SOEM's way of counting: every frame back within 2 ms with its full working counter.
  EXPECT_TRUE(contains(out.out, "cycles_valid_within_2ms: 100 cycles (as SOEM's test counts")) << out.out;
}

TEST(BenchMasterScheduling, DefaultIsTheEthercatTasksRealTimeSetUp) {
  const test::CommandOutput out = test::run_command(kBinary + " bench master --cycles 100 2>&1");
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "scheduling: rt (SCHED_FIFO 80, CPU 1)")) << out.out;
  EXPECT_TRUE(contains(out.out, "receive_wait: sleep, spin at most 150 us")) << out.out;
}

TEST(BenchMasterScheduling, ReceiveWaitIsChosenOrRefused) {
  const test::CommandOutput out = test::run_command(kBinary + " bench master --receive-wait spin --receive-spin-us 40 --cycles 100 2>&1");
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "receive_wait: spin, spin at most 40 us")) << out.out;
  const test::CommandOutput bad = test::run_command(kBinary + " bench master --receive-wait busy 2>&1");
  EXPECT_NE(bad.exit_status, 0) << bad.out;
  EXPECT_TRUE(contains(bad.out, "--receive-wait must be spin, adaptive or sleep")) << bad.out;
}

TEST(BenchMasterScheduling, AnythingElseIsRefused) {
  const test::CommandOutput out = test::run_command(kBinary + " bench master --scheduling fast 2>&1");
  EXPECT_NE(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "--scheduling must be rt or normal")) << out.out;
}

}  // namespace
}  // namespace rescue::app
