// The master over the raw-socket NIC (real time, CLOCK_MONOTONIC) against `rescue-motion sim
// --iface` at the other end of a veth pair in network namespaces: bring-up to OP, cycles
// with every joint valid, then a cable cut through the simulator's fault console: the lost joints
// are reported exactly while the others keep running, the restored link is reported and the
// joints come back only when re-integrated. With online recovery on: a drive power-cycled and a
// branch cut and reconnected through the fault console come back to OP by themselves, a foreign
// device is refused, and the other joints keep running.
#include <gtest/gtest.h>

#include <signal.h>

#include <cstdio>

#include "tests/support/master_over_veth.hpp"

namespace rescue::app {
namespace {

using MasterOverVeth = rescue::testing::MasterOverVethTest;

TEST_F(MasterOverVeth, ReachesOpAndReportsACutExactly) {
  ecat::MasterOptions options;
  // A loaded test machine, not a real-time one: round trips over veth to the simulator process
  // reach milliseconds now and then, so generous timeouts and a 4 ms cycle.
  options.drift_compensation_frames = 3000;
  options.frame_timeout = 20 * hal::kNsPerMs;
  options.cycle_time = 4 * hal::kNsPerMs;
  options.cycle_receive_timeout = 3500 * hal::kNsPerUs;
  bring_up_to_op(options, 1000);
  if (HasFatalFailure()) return;
  int all_valid = 0;
  for (int i = 0; i < 500; ++i) all_valid += cycle().valid == kAllJoints ? 1 : 0;
  EXPECT_GE(all_valid, 495) << "cycles with every joint valid (a late frame on a loaded machine is tolerated)";

  const JointMask lost = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(sim_.write_input("cut l_elbow\n"));
  for (int i = 0; i < 2000 && reported(ecat::LinkEventKind::lost) == 0; ++i) (void)cycle();
  EXPECT_EQ(reported(ecat::LinkEventKind::lost), lost);
  for (int i = 0; i < 100; ++i) {
    const drivers::JointCycleResult r = cycle();
    if (r.frame_received) {
      EXPECT_EQ(r.valid, kAllJoints & ~lost);
    }
  }

  ASSERT_TRUE(sim_.write_input("restore l_elbow\n"));
  for (int i = 0; i < 2000 && reported(ecat::LinkEventKind::restored) != lost; ++i) (void)cycle();
  EXPECT_EQ(reported(ecat::LinkEventKind::restored), lost);
  ASSERT_TRUE(bus_->reintegrate(lost));
  for (int i = 0; i < 200 && reported(ecat::LinkEventKind::reintegrated) != lost; ++i) (void)cycle();
  EXPECT_EQ(reported(ecat::LinkEventKind::reintegrated), lost);
  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
}

TEST_F(MasterOverVeth, RecoversAPowerCycledDriveAndAReconnectedBranchOnline) {
  ecat::MasterOptions options;
  options.drift_compensation_frames = 3000;
  options.frame_timeout = 20 * hal::kNsPerMs;
  options.cycle_time = 4 * hal::kNsPerMs;
  options.cycle_receive_timeout = 3500 * hal::kNsPerUs;
  options.online_recovery = true;
  bring_up_to_op(options, 1000);
  if (HasFatalFailure()) return;
  // Cycles until reports of `kind` covered `joints` (or `limit` cycles); the cycles taken.
  const auto cycles_until = [this](ecat::LinkEventKind kind, JointMask joints, int limit) {
    int i = 0;
    for (; i < limit && (reported(kind) & joints) != joints; ++i) (void)cycle();
    return i;
  };
  const JointMask hand = joint_bit(joint_index_by_name("r_hand"));
  ASSERT_TRUE(sim_.write_input("power-cycle r_hand\n"));
  int cycles = cycles_until(ecat::LinkEventKind::recovered, hand, 3000);
  EXPECT_EQ(reported(ecat::LinkEventKind::recovered) & hand, hand);
  std::printf("veth: power-cycled r_hand back in OP after %d periods of 4 ms\n", cycles);

  const JointMask branch = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(sim_.write_input("cut l_elbow\n"));
  (void)cycles_until(ecat::LinkEventKind::lost, branch, 2000);
  EXPECT_EQ(reported(ecat::LinkEventKind::lost) & branch, branch);
  ASSERT_TRUE(sim_.write_input("restore l_elbow\n"));
  cycles = cycles_until(ecat::LinkEventKind::recovered, branch | hand, 3000);
  EXPECT_EQ(reported(ecat::LinkEventKind::recovered) & branch, branch);
  std::printf("veth: reconnected l_elbow..l_hand back in OP after %d periods of 4 ms\n", cycles);

  ASSERT_TRUE(sim_.write_input("foreign neck_tilt\n"));
  const JointMask tilt = joint_bit(joint_index_by_name("neck_tilt"));
  (void)cycles_until(ecat::LinkEventKind::recovery_refused, tilt, 3000);
  EXPECT_EQ(reported(ecat::LinkEventKind::recovery_refused) & tilt, tilt);

  int all_valid = 0;
  for (int i = 0; i < 200; ++i) all_valid += (cycle().valid | tilt) == kAllJoints ? 1 : 0;
  EXPECT_GE(all_valid, 195) << "every joint but the refused one back (a late frame on a loaded machine is tolerated)";
  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
}

}  // namespace
}  // namespace rescue::app
