// `bench master --nic sim --ring-nic sim` measures the redundant master on the simulated robot's ring
// configuration (docs/redundancy.md): the robots built as the ring, both master ports on them, the
// ring closed at the end with every joint valid; a cable cut and restored in the measured run
// (--ring-cut) costs no cycle and keeps the clocks (issue 34 item 3's figures); a raw ring port beside
// the simulated main one, and --ring-cut without the ring, are refused with the reason.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(BenchMasterOnTheSimulatedRing, RunsWithBothPortsAndTheRingClosed) {
  const test::CommandOutput out =
      test::run_command(kBinary + " bench master --nic sim --ring-nic sim --scheduling normal --cycles 100 --ring-cut none 2>&1");
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "ring_nic: sim (the simulated robot's ring port)")) << out.out;
  EXPECT_TRUE(contains(out.out, "ring_state: closed (breaks 0, repairs 0, 0 changes in the measured run)")) << out.out;
  EXPECT_TRUE(contains(out.out, "slaves: 23 slaves")) << out.out;
  EXPECT_TRUE(contains(out.out, "cycles_all_joints_valid: 100 cycles")) << out.out;
  // The cold start and the warm bring-up ran on their own ring robots too.
  EXPECT_TRUE(contains(out.out, "bring_up_sii_cached_to_op:")) << out.out;
  EXPECT_TRUE(contains(out.out, "dc_cold_cycles_to_100ns:")) << out.out;
}

// The number after `key: ` on its line (-1 when the line is missing).
long figure(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key + ": ");
  return at == std::string::npos ? -1 : std::strtol(text.c_str() + at + key.size() + 2, nullptr, 10);
}

TEST(BenchMasterOnTheSimulatedRing, ACableCutInTheMeasuredRunCostsNoCycleAndKeepsTheClocks) {
  const test::CommandOutput out = test::run_command(
      kBinary + " bench master --nic sim --ring-nic sim --scheduling normal --cycles 400 --ring-cut 12 --cold-start no 2>&1");
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "ring_cut: the cable into r_track, cut after cycle 133, restored after cycle 266")) << out.out;
  EXPECT_TRUE(contains(out.out, "2 changes in the measured run")) << out.out;
  EXPECT_TRUE(contains(out.out, "cycles_all_joints_valid: 400 cycles")) << out.out;
  const long after_break = figure(out.out, "ring_dc_max_difference_after_break");
  const long moved = figure(out.out, "ring_dc_sync0_moved_max");
  const long after_repair = figure(out.out, "ring_dc_max_difference_after_repair");
  EXPECT_GE(after_break, 0) << out.out;
  EXPECT_LE(after_break, 100) << out.out;
  EXPECT_GE(moved, 0) << out.out;
  EXPECT_LE(moved, 1000) << out.out;
  EXPECT_GE(after_repair, 0) << out.out;
  // So soon after bring-up the loops are still settling: the bound of a break here; back to the
  // no-fault figures at rest: test_ring_keeps_every_clock_synchronised_across_any_single_cut.
  EXPECT_LE(after_repair, 100) << out.out;
}

TEST(BenchMasterOnTheSimulatedRing, ARingCutWithoutTheRingIsRefused) {
  const test::CommandOutput out = test::run_command(kBinary + " bench master --nic sim --ring-cut 3 --cycles 100 2>&1");
  EXPECT_NE(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "--ring-cut needs --nic sim --ring-nic sim")) << out.out;
}

TEST(BenchMasterOnTheSimulatedRing, ARawRingPortBesideTheSimulatedMainIsRefused) {
  const test::CommandOutput out = test::run_command(kBinary + " bench master --nic sim --ring-nic raw:lo --cycles 100 2>&1");
  EXPECT_NE(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "--ring-nic raw:IFACE needs --nic raw:IFACE")) << out.out;
}

}  // namespace
}  // namespace rescue::app
