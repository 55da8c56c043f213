// The redundant master on the simulated robot's ring configuration, end to end on virtual time: the
// bring-up to OP over both ports (DC measured on the line, docs/redundancy.md "DC on the ring"); then,
// while cycling, each of the 24 cables cut and restored in turn: no joint lost, every cycle's working
// counters full, the break reported once with its place and the repair once. Two cuts lose exactly the
// slaves between them, and both repaired the ring closes and every joint comes back.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "drivers/joint/joint_bus.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "hal/time/clock.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

constexpr std::size_t kRingCable = kSlaveCount;  // cable k < kSlaveCount: the cable into position k's port 0
constexpr int kCyclesPerStep = 30;

drivers::RobotSegmentOptions ring_options() {
  drivers::RobotSegmentOptions options;
  options.ring = true;
  return options;
}

struct RingRig {
  hal::VirtualClock clock{hal::kNsPerSec};
  drivers::SimulatedRobot robot{ring_options(), clock.now()};
  drivers::SimulatedNicPair nics{robot.segment(), clock};
  drivers::JointBus bus{nics.main(), drivers::kRobotRingNetworkPlan};

  RingRig() { bus.master().use_ring(nics.ring()); }

  drivers::JointCycleResult cycle(drivers::JointFeedback& feedback) {
    clock.sleep_until(bus.next_wakeup());
    return bus.cycle(references, feedback);
  }

  Status cut(std::size_t cable) {
    return cable == kRingCable ? robot.segment().cut_ring_cable() : robot.segment().cut_link(cable);
  }
  Status restore(std::size_t cable) {
    return cable == kRingCable ? robot.segment().restore_ring_cable() : robot.segment().restore_link(cable);
  }

  drivers::JointReferences references{};
};

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
  EXPECT_TRUE(rig->robot.status().ok()) << rig->robot.status().error().what;
  EXPECT_TRUE(rig->nics.status().ok()) << rig->nics.status().error().what;
  const Status up = rig->bus.bring_up(testing::fast_options());
  EXPECT_TRUE(up.ok()) << testing::describe_master_failure(rig->bus.master());
  if (!up.ok()) return rig;
  drivers::JointFeedback fb{};
  for (int i = 0; i < 200 && rig->bus.master().state() != MasterState::op; ++i) (void)rig->cycle(fb);
  EXPECT_EQ(rig->bus.master().state(), MasterState::op) << testing::describe_master_failure(rig->bus.master());
  return rig;
}

// The place a cut of `cable` opens: the last slave the main port reaches and the first the ring port does.
std::uint8_t place_before(std::size_t cable) { return cable == 0 ? kMainPort : static_cast<std::uint8_t>(cable - 1); }
std::uint8_t place_after(std::size_t cable) { return cable == kRingCable ? kRingPort : static_cast<std::uint8_t>(cable); }

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
  drivers::JointFeedback fb{};
  for (int i = 0; i < kCyclesPerStep; ++i) (void)rig->cycle(fb);
  RingReport ring_report;
  while (master.pop_ring_report(ring_report)) {
  }
  drivers::JointLinkReport link_report;
  while (rig->bus.pop_report(link_report)) {
  }

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
  // The ring's report of `kind`, once, at the place of `cable`.
  const auto expect_one_report = [&](RingEventKind kind, std::size_t cable) {
    ASSERT_TRUE(master.pop_ring_report(ring_report)) << "cable " << cable << ": no " << to_string(kind) << " report";
    EXPECT_EQ(ring_report.kind, kind) << "cable " << cable;
    EXPECT_EQ(ring_report.before, place_before(cable)) << "cable " << cable;
    EXPECT_EQ(ring_report.after, place_after(cable)) << "cable " << cable;
    EXPECT_FALSE(master.pop_ring_report(ring_report)) << "cable " << cable << ": a second report " << to_string(ring_report.kind);
  };
  for (std::size_t cable = 0; cable <= kRingCable; ++cable) {
    ASSERT_TRUE(rig->cut(cable).ok()) << cable;
    run_step();
    EXPECT_EQ(master.ring_status().state, RingState::open) << "cable " << cable;
    EXPECT_EQ(master.ring_status().before, place_before(cable)) << "cable " << cable;
    EXPECT_EQ(master.ring_status().after, place_after(cable)) << "cable " << cable;
    expect_one_report(RingEventKind::opened, cable);

    ASSERT_TRUE(rig->restore(cable).ok()) << cable;
    run_step();
    EXPECT_EQ(master.ring_status().state, RingState::closed) << "cable " << cable;
    expect_one_report(RingEventKind::closed, cable);
    while (rig->bus.pop_report(link_report)) {
      EXPECT_NE(link_report.link.kind, LinkEventKind::lost) << "cable " << cable << ": joints " << link_report.joints;
    }
  }
  EXPECT_EQ(master.ring_status().breaks, kRingCable + 1);
  EXPECT_EQ(master.ring_status().repairs, kRingCable + 1);
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
