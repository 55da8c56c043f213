// Over two veth pairs against `rescue-motion sim --iface A --ring-iface B` (the robot's ring
// configuration; wall clock, raw sockets, 1 ms period): the master with both ports (the ring plan,
// docs/redundancy.md) while cables are cut and restored one at a time through the simulator's fault
// console, the fault falling wherever the simulator is (between two frames, or between the two
// copies of one frame). For each cable: no joint is lost, the break is reported once with its place
// and the repair once, and a cycle misses a joint only when a copy came back late (host jitter on a
// loaded machine, counted apart).
#include <gtest/gtest.h>

#include <signal.h>

#include <cstdio>
#include <string>

#include "tests/support/master_over_veth.hpp"
#include "tests/support/ring_robot_rig.hpp"

namespace rescue::app {
namespace {

class RingOverVeth : public rescue::testing::MasterOverVethTest {
 protected:
  bool ring() const override { return true; }
};

struct Cable {
  const char* name;  // the fault console's name: the slave the cable leads into, or "ring"
  std::size_t cable;  // position (the cable into its port 0), or testing::kRingCable
};

TEST_F(RingOverVeth, CuttingCablesOneAtATimeLosesNoJointAndReportsEachBreakAndRepairOnce) {
  ecat::MasterOptions options;
  options.drift_compensation_frames = 3000;
  options.frame_timeout = 20 * hal::kNsPerMs;
  bring_up_to_op(options, 3000);
  if (HasFatalFailure()) return;
  ecat::Master& master = bus_->master();
  ASSERT_EQ(master.ring_status().state, ecat::RingState::closed);
  for (int i = 0; i < 100; ++i) (void)cycle();
  ecat::RingReport dropped;
  while (master.pop_ring_report(dropped)) {
  }
  reports_.clear();

  const Cable cables[] = {{"junction_b", 1}, {"r_elbow", 5}, {"l_leg", 9}, {"neck_pan", 14}, {"l_hand", 22},
                          {"ring", rescue::testing::kRingCable}};
  int cycles = 0;
  int joint_cycles_missed = 0;
  int cycles_missed = 0;
  int cycles_with_a_late_copy = 0;
  int missed_without_a_late_copy = 0;
  const auto run = [&](int count) {
    for (int i = 0; i < count; ++i) {
      const ecat::LinkStats before = master.link().stats();
      const drivers::JointCycleResult r = cycle();
      const ecat::LinkStats& after = master.link().stats();
      const bool late = !r.frame_received || after.timeouts != before.timeouts || after.stale_frames != before.stale_frames;
      const JointMask missed = kAllJoints & ~r.valid;
      ++cycles;
      cycles_with_a_late_copy += late ? 1 : 0;
      cycles_missed += missed != 0 ? 1 : 0;
      missed_without_a_late_copy += missed != 0 && !late ? 1 : 0;
      joint_cycles_missed += ecat::popcount(missed);
    }
  };
  for (const Cable& c : cables) {
    if (c.cable < kSlaveCount) {
      ASSERT_STREQ(drivers::kRobotRingNetworkPlan[c.cable].name, c.name);
    }
    ASSERT_TRUE(sim_.write_input(std::string("cut ") + c.name + "\n"));
    run(300);
    EXPECT_TRUE(sim_.wait_for_output(std::string("fault: ok cut ") + c.name, kStartTimeoutMs)) << sim_.output();
    EXPECT_EQ(master.ring_status().state, ecat::RingState::open) << c.name;
    rescue::testing::expect_one_ring_report(master, ecat::RingEventKind::opened, c.cable);
    ASSERT_TRUE(sim_.write_input(std::string("restore ") + c.name + "\n"));
    run(300);
    EXPECT_TRUE(sim_.wait_for_output(std::string("fault: ok restore ") + c.name, kStartTimeoutMs)) << sim_.output();
    EXPECT_EQ(master.ring_status().state, ecat::RingState::closed) << c.name;
    rescue::testing::expect_one_ring_report(master, ecat::RingEventKind::closed, c.cable);
  }
  EXPECT_EQ(reported(ecat::LinkEventKind::lost), 0U) << "no joint lost to a single cut";
  EXPECT_EQ(master.ring_status().breaks, std::size(cables));
  EXPECT_EQ(master.ring_status().repairs, std::size(cables));
  EXPECT_EQ(missed_without_a_late_copy, 0) << "a joint missed a cycle whose copies all came back in time";
  std::printf("ring over veth: %d cycles over %zu cuts and repairs: %d cycles missed a joint (%d joint-cycles), %d cycles with "
              "a late copy, %llu exchanges repeated, %llu transients\n",
              cycles, std::size(cables), cycles_missed, joint_cycles_missed, cycles_with_a_late_copy,
              static_cast<unsigned long long>(master.link().stats().ring_repeats),
              static_cast<unsigned long long>(master.ring_status().transients));
  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
}

}  // namespace
}  // namespace rescue::app
