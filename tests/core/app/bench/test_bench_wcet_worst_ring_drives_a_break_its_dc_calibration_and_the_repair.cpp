// Issue 38, `rescue-motion bench wcet --scenario worst-ring` (docs/timing.md "Worst-path scenarios"):
// the handler's heaviest path on the ring configuration is driven within the scenario's periods. On
// the simulated robot's ring (both master ports, in virtual time) the cut of the master's cable opens
// the ring and the repair closes it, each counted by the ring monitor; across the break the ring DC
// service completes a calibration (latch, reads of every DC slave behind the break) and writes the
// ring-side times; a damaged frame with the ring closed has its exchange sent again; every slave is
// power-cycled and recovered with no failed attempt, frames damaged while they recover too (issue 34),
// and nothing is allocated after init. The figures
// are the master's counters as the bench prints them; no timing is asserted (--scheduling normal).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "tests/support/key_value_output.hpp"
#include "tests/support/run_command.hpp"

namespace rescue {
namespace {

using test::value_of;
const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

long count_of(const std::string& text, const std::string& key) { return std::atol(value_of(text, key).c_str()); }

TEST(BenchWcetWorstRing, DrivesABreakItsDcCalibrationTheRepeatAndTheRepairWithEveryOtherService) {
  if (test::run_command("/usr/bin/python3 -c 'import scipy' 2>/dev/null").exit_status != 0) {
    GTEST_SKIP() << "/usr/bin/python3 cannot import scipy (toolchain/setup.sh)";
  }
  char dir[64] = "/tmp/test-bench-wcet-ring-XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  const test::CommandOutput run = test::run_command("'" + kProgram + "' bench wcet --short --scenario worst-ring --periods 2000 " +
                                                    "--scheduling normal --no-plot --out " + dir + "/out 2>&1");
  (void)std::system(("rm -rf '" + std::string(dir) + "'").c_str());
  const std::string& out = run.out;
  ASSERT_TRUE(run.exit_status == 0 || run.exit_status == 2 || run.exit_status == 3) << out;
  EXPECT_NE(value_of(out, "scenario").rfind("worst-ring (", 0), std::string::npos) << out;
  EXPECT_EQ(value_of(out, "heap_allocations_after_init"), "0 allocations") << out;
  // The break and the repair, each seen once per cut.
  const long cuts = count_of(out, "cable_cuts_repaired");
  EXPECT_GE(cuts, 1) << out;
  EXPECT_EQ(count_of(out, "ring_breaks"), cuts) << out;
  EXPECT_EQ(count_of(out, "ring_repairs"), cuts) << out;
  // DC across the break: a calibration completed, the ring-side times written.
  EXPECT_GE(count_of(out, "ring_dc_calibrations"), 1) << out;
  EXPECT_GT(count_of(out, "ring_dc_island_reads"), 0) << out;
  // A damaged frame with the ring closed: the exchange sent again.
  EXPECT_GE(count_of(out, "damaged_frames"), 1) << out;
  EXPECT_GE(count_of(out, "ring_repeats"), 1) << out;
  // Every other service as in worst: the slaves power-cycled and recovered, the operator's load.
  EXPECT_GE(count_of(out, "power_cycles_of_every_slave"), 1) << out;
  EXPECT_GE(count_of(out, "recoveries_to_every_joint_enabled"), 1) << out;
  EXPECT_NE(value_of(out, "master_recoveries").find(", 0 attempts failed,"), std::string::npos) << out;
  EXPECT_GT(count_of(out, "sdo_transfers"), 100) << out;
  EXPECT_EQ(value_of(out, "socket_handler_max_datagrams_per_wakeup"), "64 (its budget 64)") << out;
}

}  // namespace
}  // namespace rescue
