// Issue 36 "Done means": `ctl sdos` and `ctl pdos` over veth, the path of the robot (the master on a
// raw socket, the segment served by `rescue-motion sim --iface` in another network namespace),
// not the in-process simulator: ctl in the master's namespace lists r_hand's dictionary (31 objects,
// 0x1018 a RECORD) and reads its PDOs back the same as configured, and a junction is refused by
// sdos (no mailbox) and said by pdos to map none. Skipped where network namespaces cannot be made
// (CI must make them: tests/support/netns_veth.hpp).
#include <gtest/gtest.h>

#include <csignal>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/netns_veth.hpp"

namespace rescue::app {
namespace {

using rescue::testing::ChildProcess;
using rescue::testing::VethPair;

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
constexpr int kTimeoutMs = 30000;
const std::string kControlPort = "47010";  // the master's namespace is fresh: any port is free

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

class CtlOverVeth : public rescue::testing::NetnsTest {
 protected:
  struct Answer {
    int status;
    std::string out;
  };
  Answer ctl(std::vector<std::string> args) {
    args.insert(args.begin(), {kBinary, "ctl", "--key", key_, "--port", kControlPort});
    ChildProcess c;
    if (!c.start(args, veth_->master_ns())) return {-1, "not started"};
    const int status = c.wait_exit();
    return {status, c.output()};
  }
  testing::TempStateDir dir_;
  std::string key_ = dir_.path + "/operator.key";
};

TEST_F(CtlOverVeth, SdosAndPdosReadADriveThroughTheRawSocket) {
  std::string out;
  ASSERT_TRUE(VethPair::ip(veth_->master_ns(), "link set lo up", out)) << out;  // ctl and run meet on 127.0.0.1
  ChildProcess keygen;
  ASSERT_TRUE(keygen.start({kBinary, "ctl", "keygen", "--key", key_}));
  ASSERT_EQ(keygen.wait_exit(), 0) << keygen.output();
  ChildProcess sim;
  ASSERT_TRUE(sim.start({kBinary, "sim", "--iface", VethPair::kSlaveInterface}, veth_->slave_ns()));
  ASSERT_TRUE(sim.wait_for_output("serving 23 slaves", kTimeoutMs)) << sim.output();
  ChildProcess run;
  ASSERT_TRUE(run.start({kBinary, "run", "--nic", std::string("raw:") + VethPair::kMasterInterface, "--duration", "60",
                         "--state-dir", dir_.path, "--key", key_, "--listen", "127.0.0.1", "--control-port", kControlPort,
                         "--sensor-port", "47011"},
                        veth_->master_ns()));
  ASSERT_TRUE(run.wait_for_output("network in OP", kTimeoutMs)) << run.output();

  const Answer sdos = ctl({"sdos", "r_hand"});
  EXPECT_EQ(sdos.status, 0) << sdos.out;
  EXPECT_TRUE(has(sdos.out, ": 31 objects, as the slave describes them (CoE SDO Information)\n")) << sdos.out;
  EXPECT_TRUE(has(sdos.out, "SDO 0x1018, RECORD, max subindex 4, \"Identity\"\n")) << sdos.out;
  const Answer junction = ctl({"sdos", "junction_a"});
  EXPECT_EQ(junction.status, 1) << junction.out;
  EXPECT_TRUE(has(junction.out, "refused: no mailbox")) << junction.out;

  const Answer pdos = ctl({"pdos", "r_hand"});
  EXPECT_EQ(pdos.status, 0) << pdos.out;
  EXPECT_TRUE(has(pdos.out, "[same]")) << pdos.out;
  EXPECT_FALSE(has(pdos.out, "differs")) << pdos.out;
  const Answer none = ctl({"pdos", "junction_a"});
  EXPECT_EQ(none.status, 0) << none.out;
  EXPECT_TRUE(has(none.out, "it maps no PDO")) << none.out;

  EXPECT_EQ(run.stop(SIGTERM), 0) << run.output();
  (void)sim.stop(SIGTERM);
}

}  // namespace
}  // namespace rescue::app
