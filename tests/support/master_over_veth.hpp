// Test support: our master over the raw-socket NIC (wall clock) against `rescue-motion sim --iface`
// at the other end of a fresh veth pair in network namespaces. The simulator gets a real-time
// priority when the machine allows (root), standing for slave hardware that a busy test machine does
// not delay by milliseconds, and the test's thread (the master) one below it, as the EtherCAT handler
// has on the motion PC: a busy CI machine then delays neither side's wake-ups. cycle() sleeps to the master's wake-up, runs one cycle and collects the
// joint link reports in reports_. With ring() true the simulator serves the ring configuration on a
// second veth pair too (`sim --ring-iface`), and the master runs the ring plan with both NICs
// (docs/redundancy.md). Tests only.
#pragma once

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/joint/joint_bus.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "hal/net/raw_socket_nic.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/netns_veth.hpp"

namespace rescue::testing {

class MasterOverVethTest : public NetnsTest {
 protected:
  static constexpr int kStartTimeoutMs = 10000;
  static constexpr int kMasterPriority = 60;  // below the simulator's 70 (chrt -f 70 below)

  // Extra arguments of `sim` (e.g. "--through-qdisc"); override before SetUp runs.
  virtual std::vector<std::string> sim_arguments() const { return {}; }
  // The ring configuration on a second veth pair (its interfaces kRingMaster, kRingSlave).
  virtual bool ring() const { return false; }
  static constexpr const char* kRingMaster = "ecm1";
  static constexpr const char* kRingSlave = "ecs1";

  void SetUp() override {
    NetnsTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    std::vector<std::string> argv{std::string(RESCUE_BINARY_DIR) + "/rescue-motion", "sim", "--iface",
                                  VethPair::kSlaveInterface};
    for (const std::string& a : sim_arguments()) argv.push_back(a);
    if (ring()) {
      std::string out;
      ASSERT_TRUE(VethPair::ip(veth_->master_ns(), std::string("link add name ") + kRingMaster + " type veth peer name " +
                                                       kRingSlave + " netns " + veth_->slave_ns(), out))
          << out;
      ASSERT_TRUE(VethPair::ip(veth_->master_ns(), std::string("link set ") + kRingMaster + " up", out)) << out;
      ASSERT_TRUE(VethPair::ip(veth_->slave_ns(), std::string("link set ") + kRingSlave + " up", out)) << out;
      argv.insert(argv.end(), {"--ring-iface", kRingSlave});
    }
    if (::geteuid() == 0 && ::access("/usr/bin/chrt", X_OK) == 0) argv.insert(argv.begin(), {"/usr/bin/chrt", "-f", "70"});
    ASSERT_TRUE(sim_.start(argv, veth_->slave_ns()));
    ASSERT_TRUE(sim_.wait_for_output(ring() ? "serving 23 slaves in a ring on" : "serving 23 slaves on", kStartTimeoutMs))
        << sim_.output();
    sched_param master_priority{};
    master_priority.sched_priority = kMasterPriority;
    master_is_real_time_ = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &master_priority) == 0;
    InNamespace inside(veth_->master_ns());
    ASSERT_TRUE(inside.entered());
    ASSERT_TRUE(nic_.open(VethPair::kMasterInterface).ok());
    if (ring()) {
      ASSERT_TRUE(ring_nic_.open(kRingMaster).ok());
      bus_ = std::make_unique<drivers::JointBus>(nic_, drivers::kRobotRingNetworkPlan);
      bus_->master().use_ring(ring_nic_);
    } else {
      bus_ = std::make_unique<drivers::JointBus>(nic_);
    }
  }

  void TearDown() override {
    if (master_is_real_time_) {
      const sched_param normal{};
      (void)::pthread_setschedparam(::pthread_self(), SCHED_OTHER, &normal);
    }
    NetnsTest::TearDown();
  }

  drivers::JointCycleResult cycle() {
    nic_.clock().sleep_until(bus_->next_wakeup());
    const drivers::JointCycleResult r = bus_->cycle(refs_, feedback_);
    drivers::JointLinkReport report;
    while (bus_->pop_report(report)) reports_.push_back(report);
    return r;
  }

  // Brings the bus up with `options` and cycles until OP (at most `max_cycles`).
  void bring_up_to_op(const ecat::MasterOptions& options, int max_cycles) {
    const Status up = bus_->bring_up(options);
    ASSERT_TRUE(up.ok()) << bus_->master().report().failed_step << ": " << up.error().what;
    for (int i = 0; i < max_cycles && bus_->master().state() != ecat::MasterState::op; ++i) (void)cycle();
    ASSERT_EQ(bus_->master().state(), ecat::MasterState::op);
  }

  // The joints of every report of `kind` so far.
  JointMask reported(ecat::LinkEventKind kind) const {
    JointMask joints = 0;
    for (const drivers::JointLinkReport& r : reports_) joints |= r.link.kind == kind ? r.joints : 0;
    return joints;
  }

  bool master_is_real_time_{false};
  ChildProcess sim_;
  hal::RawSocketNic nic_;
  hal::RawSocketNic ring_nic_;
  std::unique_ptr<drivers::JointBus> bus_;
  drivers::JointReferences refs_{};
  drivers::JointFeedback feedback_{};
  std::vector<drivers::JointLinkReport> reports_;
};

}  // namespace rescue::testing
