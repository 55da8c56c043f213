// The master over the raw-socket NIC (real time, CLOCK_MONOTONIC) against `rescue-motion sim
// --iface` at the other end of a veth pair in network namespaces: bring-up to OP, cycles
// with every joint valid, then a cable cut through the simulator's fault console: the lost joints
// are reported exactly while the others keep running, the restored link is reported and the
// joints come back only when re-integrated. With online recovery on: a drive power-cycled and a
// branch cut and reconnected through the fault console come back to OP by themselves, a foreign
// device is refused, and the other joints keep running.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "drivers/joint/joint_bus.hpp"
#include "hal/net/raw_socket_nic.hpp"
#include "tests/support/child_process.hpp"
#include "tests/support/netns_veth.hpp"

namespace rescue::app {
namespace {

using rescue::testing::ChildProcess;
using rescue::testing::InNamespace;
using rescue::testing::VethPair;

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
constexpr int kStartTimeoutMs = 10000;

class MasterOverVeth : public rescue::testing::NetnsTest {
 protected:
  void SetUp() override {
    NetnsTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    // The simulator stands for slave hardware: give it a real-time priority when the machine
    // allows (root), so the other load of a test machine does not delay its answers by milliseconds.
    std::vector<std::string> argv{kBinary, "sim", "--iface", VethPair::kSlaveInterface};
    if (::geteuid() == 0 && ::access("/usr/bin/chrt", X_OK) == 0) argv.insert(argv.begin(), {"/usr/bin/chrt", "-f", "70"});
    ASSERT_TRUE(sim_.start(argv, veth_->slave_ns()));
    ASSERT_TRUE(sim_.wait_for_output("serving 23 slaves on", kStartTimeoutMs)) << sim_.output();
    InNamespace inside(veth_->master_ns());
    ASSERT_TRUE(inside.entered());
    ASSERT_TRUE(nic_.open(VethPair::kMasterInterface).ok());
    bus_ = std::make_unique<drivers::JointBus>(nic_);
  }

  // Bring-up to OP with the timeouts of a loaded test machine, not a real-time one: round trips over
  // veth to the simulator process reach milliseconds now and then, so a 4 ms cycle.
  void bring_up_to_op(bool online_recovery) {
    ecat::MasterOptions options;
    options.drift_compensation_frames = 3000;
    options.frame_timeout = 20 * hal::kNsPerMs;
    options.cycle_time = 4 * hal::kNsPerMs;
    options.cycle_receive_timeout = 3500 * hal::kNsPerUs;
    options.online_recovery = online_recovery;
    const Status up = bus_->bring_up(options);
    ASSERT_TRUE(up.ok()) << bus_->master().report().failed_step << ": " << up.error().what;
    for (int i = 0; i < 1000 && bus_->master().state() != ecat::MasterState::op; ++i) (void)cycle();
    ASSERT_EQ(bus_->master().state(), ecat::MasterState::op);
  }

  // Cycles until reports of `kind` covered `joints` (or `limit` cycles); returns what was reported.
  JointMask wait_for(ecat::LinkEventKind kind, JointMask joints, int limit, int* cycles = nullptr) {
    ecat::LinkReport report;
    JointMask seen = 0;
    int i = 0;
    for (; i < limit && (seen & joints) != joints; ++i) {
      (void)cycle();
      while (bus_->master().pop_report(report)) {
        if (report.kind == kind) seen |= drivers::joints_of_slaves(report.slaves);
      }
    }
    if (cycles != nullptr) *cycles = i;
    return seen;
  }

  drivers::JointCycleResult cycle() {
    nic_.clock().sleep_until(bus_->next_wakeup());
    return bus_->cycle(refs_, feedback_);
  }

  ChildProcess sim_;
  hal::RawSocketNic nic_;
  std::unique_ptr<drivers::JointBus> bus_;
  drivers::JointReferences refs_{};
  drivers::JointFeedback feedback_{};
};

TEST_F(MasterOverVeth, ReachesOpAndReportsACutExactly) {
  bring_up_to_op(false);
  if (HasFatalFailure()) return;
  int all_valid = 0;
  for (int i = 0; i < 500; ++i) all_valid += cycle().valid == kAllJoints ? 1 : 0;
  EXPECT_GE(all_valid, 495) << "cycles with every joint valid (a late frame on a loaded machine is tolerated)";

  const JointMask lost = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(sim_.write_input("cut l_elbow\n"));
  ecat::LinkReport report;
  JointMask reported = 0;
  for (int i = 0; i < 2000 && reported == 0; ++i) {
    (void)cycle();
    while (bus_->master().pop_report(report)) {
      if (report.kind == ecat::LinkEventKind::lost) reported |= drivers::joints_of_slaves(report.slaves);
    }
  }
  EXPECT_EQ(reported, lost);
  for (int i = 0; i < 100; ++i) {
    const drivers::JointCycleResult r = cycle();
    if (r.frame_received) {
      EXPECT_EQ(r.valid, kAllJoints & ~lost);
    }
  }

  ASSERT_TRUE(sim_.write_input("restore l_elbow\n"));
  JointMask restored = 0;
  for (int i = 0; i < 2000 && restored != lost; ++i) {
    (void)cycle();
    while (bus_->master().pop_report(report)) {
      if (report.kind == ecat::LinkEventKind::restored) restored |= drivers::joints_of_slaves(report.slaves);
    }
  }
  EXPECT_EQ(restored, lost);
  ASSERT_TRUE(bus_->reintegrate(lost));
  JointMask back = 0;
  for (int i = 0; i < 200 && back != lost; ++i) {
    (void)cycle();
    while (bus_->master().pop_report(report)) {
      if (report.kind == ecat::LinkEventKind::reintegrated) back |= drivers::joints_of_slaves(report.slaves);
    }
  }
  EXPECT_EQ(back, lost);
  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
}

TEST_F(MasterOverVeth, RecoversAPowerCycledDriveAndAReconnectedBranchOnline) {
  bring_up_to_op(true);
  if (HasFatalFailure()) return;
  const JointMask hand = joint_bit(joint_index_by_name("r_hand"));
  int cycles = 0;
  ASSERT_TRUE(sim_.write_input("power-cycle r_hand\n"));
  EXPECT_EQ(wait_for(ecat::LinkEventKind::recovered, hand, 3000, &cycles) & hand, hand);
  std::printf("veth: power-cycled r_hand back in OP after %d periods of 4 ms\n", cycles);

  const JointMask branch = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(sim_.write_input("cut l_elbow\n"));
  EXPECT_EQ(wait_for(ecat::LinkEventKind::lost, branch, 2000), branch);
  ASSERT_TRUE(sim_.write_input("restore l_elbow\n"));
  EXPECT_EQ(wait_for(ecat::LinkEventKind::recovered, branch, 3000, &cycles), branch);
  std::printf("veth: reconnected l_elbow..l_hand back in OP after %d periods of 4 ms\n", cycles);

  ASSERT_TRUE(sim_.write_input("foreign neck_tilt\n"));
  const JointMask tilt = joint_bit(joint_index_by_name("neck_tilt"));
  EXPECT_EQ(wait_for(ecat::LinkEventKind::recovery_refused, tilt, 3000) & tilt, tilt);

  int all_valid = 0;
  for (int i = 0; i < 200; ++i) all_valid += (cycle().valid | tilt) == kAllJoints ? 1 : 0;
  EXPECT_GE(all_valid, 195) << "every joint but the refused one back (a late frame on a loaded machine is tolerated)";
  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
}

}  // namespace
}  // namespace rescue::app
