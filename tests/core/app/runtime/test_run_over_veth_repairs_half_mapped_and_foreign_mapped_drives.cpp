// `rescue-motion run` over a veth pair against `rescue-motion sim --iface` (issue 28): l_elbow's drive
// left half-mapped (0x1600 entries written, 0x1600:00 at 0) and l_leg's reset to another drive's
// default mapping before bring-up; the master rewrites both and the run reaches OP. One second into
// the run r_elbow's mapping is left half-written and its drive power-cycled: the online recovery
// rewrites it and brings it back. Judged on state: the run exits 0 and, with
// --auto-clear-power-cycled, the error-joints file ends empty after two writes (r_elbow recorded
// lost, then cleared once its drive was back in OP).
#include <string>

#include <gtest/gtest.h>

#include "core/app/tasks/error_joints_storage.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/netns_veth.hpp"

namespace rescue::app {
namespace {

using rescue::testing::ChildProcess;
using rescue::testing::VethPair;

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
constexpr int kTimeoutMs = 15000;

class RunOverVethMapping : public rescue::testing::NetnsTest {
 protected:
  void fault(const std::string& command) {
    ASSERT_TRUE(sim_.write_input(command + "\n"));
    ASSERT_TRUE(sim_.wait_for_output("fault: ok " + command, kTimeoutMs)) << sim_.output();
  }
  ChildProcess sim_;
};

TEST_F(RunOverVethMapping, WrongMappingsAreRewrittenAtBringUpAndInRecovery) {
  ASSERT_TRUE(sim_.start({kBinary, "sim", "--iface", VethPair::kSlaveInterface}, veth_->slave_ns()));
  ASSERT_TRUE(sim_.wait_for_output("serving 23 slaves", kTimeoutMs)) << sim_.output();
  fault("half-mapped l_elbow");
  fault("foreign-mapping l_leg");
  testing::TempStateDir dir;
  ChildProcess run;
  ASSERT_TRUE(run.start({kBinary, "run", "--nic", std::string("raw:") + VethPair::kMasterInterface, "--duration", "4",
                         "--auto-clear-power-cycled", "--state-dir", dir.path},
                        veth_->master_ns()));
  ASSERT_TRUE(run.wait_for_output("network in OP", kTimeoutMs)) << run.output();
  fault("half-mapped r_elbow");
  fault("power-cycle r_elbow");
  EXPECT_EQ(run.wait_exit(), 0) << run.output();
  ErrorJointsFileStorage storage(dir.path.c_str());
  const ErrorJointsLoad file = storage.load();
  ASSERT_TRUE(file.file_present) << run.output();
  EXPECT_EQ(file.decoded.contents.sequence, 2u) << run.output();  // recorded lost, then cleared
  EXPECT_TRUE(file.decoded.contents.records.empty()) << run.output();
}

}  // namespace
}  // namespace rescue::app
