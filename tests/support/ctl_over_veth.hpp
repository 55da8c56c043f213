// Test support: `ctl` against `rescue-motion run --nic raw:` in the master's network namespace, the
// segment served by `rescue-motion sim --iface` in the slave's (tests/support/netns_veth.hpp): the
// path of the robot, not the in-process simulator. start() brings both up to OP; ctl() runs one
// verb. Tests only.
#pragma once

#include <gtest/gtest.h>

#include <csignal>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/netns_veth.hpp"

namespace rescue::testing {

class CtlOverVeth : public NetnsTest {
 protected:
  static constexpr int kTimeoutMs = 30000;
  struct Answer {
    int status;
    std::string out;
  };

  static std::string binary() { return std::string(RESCUE_BINARY_DIR) + "/rescue-motion"; }
  static bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

  // The key, the simulator, and the robot's run to OP (the master's namespace is fresh: any port is free).
  void start() {
    std::string out;
    ASSERT_TRUE(VethPair::ip(veth_->master_ns(), "link set lo up", out)) << out;  // ctl and run meet on 127.0.0.1
    ChildProcess keygen;
    ASSERT_TRUE(keygen.start({binary(), "ctl", "keygen", "--key", key_}));
    ASSERT_EQ(keygen.wait_exit(), 0) << keygen.output();
    ASSERT_TRUE(sim_.start({binary(), "sim", "--iface", VethPair::kSlaveInterface}, veth_->slave_ns()));
    ASSERT_TRUE(sim_.wait_for_output("serving 23 slaves", kTimeoutMs)) << sim_.output();
    ASSERT_TRUE(run_.start({binary(), "run", "--nic", std::string("raw:") + VethPair::kMasterInterface, "--duration", "60",
                            "--state-dir", dir_.path, "--key", key_, "--listen", "127.0.0.1", "--control-port",
                            kControlPort, "--sensor-port", "47011"},
                           veth_->master_ns()));
    ASSERT_TRUE(run_.wait_for_output("network in OP", kTimeoutMs)) << run_.output();
  }
  void stop() {
    EXPECT_EQ(run_.stop(SIGTERM), 0) << run_.output();
    (void)sim_.stop(SIGTERM);
  }

  Answer ctl(std::vector<std::string> args) {
    args.insert(args.begin(), {binary(), "ctl", "--key", key_, "--port", kControlPort});
    ChildProcess c;
    if (!c.start(args, veth_->master_ns())) return {-1, "not started"};
    const int status = c.wait_exit();
    return {status, c.output()};
  }

  const std::string kControlPort = "47010";
  app::testing::TempStateDir dir_;
  std::string key_ = dir_.path + "/operator.key";
  ChildProcess sim_;
  ChildProcess run_;
};

}  // namespace rescue::testing
