// The redundant master on the simulated robot's ring configuration, end to end on virtual time: the
// bring-up to OP over both ports (DC measured on the line, docs/redundancy.md "DC on the ring"); then,
// while cycling, each of the 24 cables cut and restored in turn: no joint lost, every cycle's working
// counters full, the break reported once with its place and the repair once. Two cuts lose exactly the
// slaves between them, and both repaired the ring closes and every joint comes back.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "tests/support/ring_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::kRingCable;
using testing::place_after;
using testing::place_before;
using RingRig = testing::RingRobotRig;
constexpr int kCyclesPerStep = 30;

// A cycle whose frame came back with every branch's working counter as planned.
bool full_working_counter(const drivers::JointCycleResult& r, const CycleResult& master_cycle) {
  if (!r.frame_received) return false;
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    if (master_cycle.branch_wkc[b] != master_cycle.expected_wkc[b]) return false;
  }
  return true;
}

std::unique_ptr<RingRig> ring_in_op() {
  auto rig = std::make_unique<RingRig>();
  testing::bring_ring_to_op(*rig, rig->nics.ring());
  return rig;
}

TEST(MasterOnTheRing, BringsTheRingUpToOpWithTheClocksSynchronised) {
  auto rig = ring_in_op();
  ASSERT_EQ(rig->bus.master().state(), MasterState::op);
  const Master& master = rig->bus.master();
  EXPECT_EQ(master.report().slaves_counted, kSlaveCount);
  EXPECT_EQ(master.operated(), kAllSlaves);
  EXPECT_EQ(master.ring_status().state, RingState::closed);
  // Every delay grows along the line (the ring's end closed for the latch, docs/redundancy.md).
  for (std::size_t p = 1; p < kSlaveCount; ++p) EXPECT_GT(master.report().delays[p], master.report().delays[p - 1]) << p;
  std::printf("ring bring-up: DC max diff %u ns, delay to l_hand %u ns\n", master.report().dc_max_difference_ns,
              master.report().delays[kSlaveCount - 1]);
}

TEST(MasterOnTheRing, CuttingEachOfThe24CablesInTurnLosesNoJointAndReportsBreakAndRepairOnce) {
  auto rig = ring_in_op();
  ASSERT_EQ(rig->bus.master().state(), MasterState::op);
  Master& master = rig->bus.master();
  testing::cycle_and_drop_reports(*rig, kCyclesPerStep);
  drivers::JointFeedback fb{};
  drivers::JointLinkReport link_report;

  std::uint64_t cycles = 0;
  std::uint64_t short_cycles = 0;
  JointMask joints_missing = 0;
  const auto run_step = [&] {
    for (int i = 0; i < kCyclesPerStep; ++i) {
      const drivers::JointCycleResult r = rig->cycle(fb);
      ++cycles;
      if (!full_working_counter(r, rig->bus.last_cycle())) ++short_cycles;
      joints_missing |= kAllJoints & ~r.valid;
    }
  };
  for (std::size_t cable = 0; cable <= kRingCable; ++cable) {
    ASSERT_TRUE(rig->cut(cable).ok()) << cable;
    run_step();
    EXPECT_EQ(master.ring_status().state, RingState::open) << "cable " << cable;
    EXPECT_EQ(master.ring_status().before, place_before(cable)) << "cable " << cable;
    EXPECT_EQ(master.ring_status().after, place_after(cable)) << "cable " << cable;
    testing::expect_one_ring_report(master, RingEventKind::opened, cable);

    ASSERT_TRUE(rig->restore(cable).ok()) << cable;
    run_step();
    EXPECT_EQ(master.ring_status().state, RingState::closed) << "cable " << cable;
    testing::expect_one_ring_report(master, RingEventKind::closed, cable);
    while (rig->bus.pop_report(link_report)) {
      EXPECT_NE(link_report.link.kind, LinkEventKind::lost) << "cable " << cable << ": joints " << link_report.joints;
    }
  }
  EXPECT_EQ(master.ring_status().breaks, kRingCable + 1);
  EXPECT_EQ(master.ring_status().repairs, kRingCable + 1);
  EXPECT_EQ(master.ring_status().transients, 0U) << "cuts between frames: every frame is evidence";
  EXPECT_EQ(joints_missing, 0U);
  std::printf("ring: %llu cycles over 24 cuts and repairs, %llu without full working counter\n",
              static_cast<unsigned long long>(cycles), static_cast<unsigned long long>(short_cycles));
  EXPECT_EQ(short_cycles, 0U);
}

TEST(MasterOnTheRing, TwoCutsLoseExactlyTheSlavesBetweenThemAndBothRepairedBringThemBack) {
  auto rig = ring_in_op();
  ASSERT_EQ(rig->bus.master().state(), MasterState::op);
  Master& master = rig->bus.master();
  drivers::JointFeedback fb{};
  for (int i = 0; i < kCyclesPerStep; ++i) (void)rig->cycle(fb);
  // The cables into l_leg (9) and neck_pan (14): slaves 9 .. 13 between them.
  constexpr std::size_t kFirst = 9;
  constexpr std::size_t kSecond = 14;
  SlaveMask between = 0;
  for (std::size_t p = kFirst; p < kSecond; ++p) between |= slave_bit(p);
  ASSERT_TRUE(rig->cut(kFirst).ok());
  ASSERT_TRUE(rig->cut(kSecond).ok());
  drivers::JointCycleResult r;
  for (int i = 0; i < 200; ++i) r = rig->cycle(fb);
  EXPECT_EQ(master.ring_status().state, RingState::lost);
  EXPECT_EQ(master.ring_status().unreachable, between);
  EXPECT_EQ(r.valid, kAllJoints & ~drivers::joints_of_slaves(between));
  SlaveMask lost = 0;
  drivers::JointLinkReport report;
  while (rig->bus.pop_report(report)) {
    if (report.link.kind == LinkEventKind::lost) lost |= report.link.slaves;
  }
  EXPECT_EQ(lost, between);

  // Both repaired: the ring closes, the slaves between come back (re-integrated once reported
  // restored, one request at a time as the joint manager does), and every joint's inputs are valid again.
  ASSERT_TRUE(rig->restore(kFirst).ok());
  ASSERT_TRUE(rig->restore(kSecond).ok());
  JointMask restored = 0;
  JointMask to_reintegrate = 0;
  for (int i = 0; i < 5000 && r.valid != kAllJoints; ++i) {
    r = rig->cycle(fb);
    while (rig->bus.pop_report(report)) {
      if (report.link.kind == LinkEventKind::restored) {
        restored |= report.joints;
        to_reintegrate |= report.joints;
      }
    }
    if (to_reintegrate != 0 && rig->bus.reintegrate(to_reintegrate)) to_reintegrate = 0;
  }
  EXPECT_EQ(restored, drivers::joints_of_slaves(between));
  EXPECT_EQ(master.ring_status().state, RingState::closed);
  EXPECT_EQ(r.valid, kAllJoints);
}

}  // namespace
}  // namespace rescue::ecat
