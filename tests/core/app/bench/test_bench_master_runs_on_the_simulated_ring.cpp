// `bench master --nic sim --ring-nic sim` measures the redundant master on the simulated robot's ring
// configuration (docs/redundancy.md): the robots built as the ring, both master ports on them, the
// ring closed at the end with every joint valid; a raw ring port beside the simulated main one is
// refused with the reason.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(BenchMasterOnTheSimulatedRing, RunsWithBothPortsAndTheRingClosed) {
  const test::CommandOutput out =
      test::run_command(kBinary + " bench master --nic sim --ring-nic sim --scheduling normal --cycles 100 2>&1");
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "ring_nic: sim (the simulated robot's ring port)")) << out.out;
  EXPECT_TRUE(contains(out.out, "ring_state: closed (breaks 0, repairs 0, 0 changes in the measured run)")) << out.out;
  EXPECT_TRUE(contains(out.out, "slaves: 23 slaves")) << out.out;
  EXPECT_TRUE(contains(out.out, "cycles_all_joints_valid: 100 cycles")) << out.out;
  // The cold start and the warm bring-up ran on their own ring robots too.
  EXPECT_TRUE(contains(out.out, "bring_up_sii_cached_to_op:")) << out.out;
  EXPECT_TRUE(contains(out.out, "dc_cold_cycles_to_100ns:")) << out.out;
}

TEST(BenchMasterOnTheSimulatedRing, ARawRingPortBesideTheSimulatedMainIsRefused) {
  const test::CommandOutput out = test::run_command(kBinary + " bench master --nic sim --ring-nic raw:lo --cycles 100 2>&1");
  EXPECT_NE(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "--ring-nic raw:IFACE needs --nic raw:IFACE")) << out.out;
}

}  // namespace
}  // namespace rescue::app
