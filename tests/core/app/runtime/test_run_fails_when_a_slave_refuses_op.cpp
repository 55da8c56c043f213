// Issue 35 item 13: a slave that refuses OP (`refuse r_hand op 0x001A` in the simulator at the other
// end of a veth pair). `run --duration 3` no longer ends "robot idle" with exit status 0: it says
// the network never reached OP, names the slave with its AL status code, and exits 1.
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/child_process.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/netns_veth.hpp"

namespace rescue::app {
namespace {

using rescue::testing::ChildProcess;
using rescue::testing::VethPair;

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
constexpr int kStartTimeoutMs = 10000;

class RunWithoutOp : public rescue::testing::NetnsTest {};

TEST_F(RunWithoutOp, ASlaveRefusingOpFailsTheRunAndIsNamedWithItsCode) {
  ChildProcess sim;
  ASSERT_TRUE(sim.start({kBinary, "sim", "--iface", VethPair::kSlaveInterface}, veth_->slave_ns()));
  ASSERT_TRUE(sim.wait_for_output("serving 23 slaves", kStartTimeoutMs)) << sim.output();
  ASSERT_TRUE(sim.write_input("refuse r_hand op 0x001A\n"));
  ASSERT_TRUE(sim.wait_for_output("fault: ok refuse r_hand op 0x001A", kStartTimeoutMs)) << sim.output();
  testing::TempStateDir dir;
  ChildProcess run;
  ASSERT_TRUE(run.start({kBinary, "run", "--nic", std::string("raw:") + VethPair::kMasterInterface, "--duration", "3",
                         "--state-dir", dir.path},
                        veth_->master_ns()));
  const int status = run.wait_exit();
  const std::string out = run.output();
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("rescue-motion run: the network never reached OP\n"), std::string::npos) << out;
  EXPECT_TRUE(std::regex_search(out, std::regex("rescue-motion run: r_hand refused OP: AL status 0x[0-9a-f]{4} "
                                                "\\([A-Z-]+, error\\), code 0x001a .*\n")))
      << out;
  EXPECT_NE(out.find("rescue-motion run: FAILED: the network never reached OP"), std::string::npos) << out;
  EXPECT_EQ(out.find("network in OP"), std::string::npos) << out;
}

}  // namespace
}  // namespace rescue::app
