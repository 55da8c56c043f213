// DC across a break of the ring (issue 34 item 3, docs/redundancy.md "DC method"), end to end on
// virtual time: the redundant master on the simulated robot's ring configuration, in OP; each of the
// 24 cables cut in turn and restored. After a break every clock keeps its place: max |0x092C| at most
// 100 ns within 100 ms of the cut, and no drive's SYNC0 edge moves by more than 1 us (its clock's
// offset from the reference's, against the offset before the cut); after the repair the no-fault
// bounds hold again. The slaves behind a break get the reference time from the ring copy only. That
// their drift loops run on (not merely that their clocks coast) is shown by a crystal step at each
// cut: every crystal but the reference's moves by 3 ppm (600 ns over a 200 ms break for a clock whose
// loop stopped; asserted at most 300 ns).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "drivers/joint/joint_bus.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "ecat/codec/registers.hpp"
#include "hal/time/clock.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

constexpr std::size_t kRingCable = kSlaveCount;  // cable k < kSlaveCount: the cable into position k's port 0
constexpr int kSettleCycles = 300;               // before the first cut: the drift loops at rest
constexpr int kCyclesWithin = 100;               // 100 ms at the 1 ms period
constexpr int kCyclesPerStep = 200;
constexpr int kCyclesAfterRepair = 400;
constexpr std::int64_t kLoopFollowsBoundNs = 300;
constexpr std::uint32_t kBreakDifferenceBoundNs = 100;
constexpr std::int64_t kSync0MoveBoundNs = 1000;
constexpr double kCrystalStepPpm = 3.0;

drivers::RobotSegmentOptions ring_options() {
  drivers::RobotSegmentOptions options;
  options.ring = true;
  return options;
}

struct RingClocksRig {
  mutable hal::VirtualClock clock{hal::kNsPerSec};  // now() is not const
  drivers::SimulatedRobot robot{ring_options(), clock.now()};
  drivers::SimulatedNicPair nics{robot.segment(), clock};
  drivers::JointBus bus{nics.main(), drivers::kRobotRingNetworkPlan};
  drivers::JointReferences references{};
  drivers::JointFeedback feedback{};

  RingClocksRig() { bus.master().use_ring(nics.ring()); }

  void cycle() {
    clock.sleep_until(bus.next_wakeup());
    (void)bus.cycle(references, feedback);
  }
  Status cut(std::size_t cable) {
    return cable == kRingCable ? robot.segment().cut_ring_cable() : robot.segment().cut_link(cable);
  }
  Status restore(std::size_t cable) {
    return cable == kRingCable ? robot.segment().restore_ring_cable() : robot.segment().restore_link(cable);
  }
  // Every crystal but the reference's moves by `step_ppm` from its configured deviation (0: back to it).
  void step_crystals(double step_ppm) {
    for (std::size_t p = 1; p < kSlaveCount; ++p) {
      drivers::Esc& esc = robot.segment().esc(p);
      esc.change_crystal_drift(clock.now(), esc.config().drift_ppm + step_ppm);
    }
  }

  // Largest |0x092C| over the slaves with distributed clocks.
  std::uint32_t max_difference() const {
    std::uint32_t worst = 0;
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      const std::uint32_t raw = robot.segment().esc(p).register_u32(reg::kDcSystemTimeDifference);
      worst = std::max(worst, raw & 0x7FFFFFFFU);
    }
    return worst;
  }
  // Each slave's system time against the reference's (position 0), at the same instant.
  std::array<std::int64_t, kSlaveCount> offsets() const {
    std::array<std::int64_t, kSlaveCount> out{};
    const hal::Nanoseconds now = clock.now();
    const std::uint64_t reference = robot.segment().esc(0).system_time_at(now);
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      out[p] = static_cast<std::int64_t>(robot.segment().esc(p).system_time_at(now) - reference);
    }
    return out;
  }
  std::int64_t true_max_offset() const {
    std::int64_t worst = 0;
    for (const std::int64_t o : offsets()) worst = std::max(worst, std::abs(o));
    return worst;
  }
  // Largest move of a drive's SYNC0 edge: its clock's offset against `before`.
  std::int64_t sync0_move(const std::array<std::int64_t, kSlaveCount>& before) const {
    const std::array<std::int64_t, kSlaveCount> now = offsets();
    std::int64_t worst = 0;
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if (kSlaves[p].kind == SlaveKind::joint_drive) worst = std::max(worst, std::abs(now[p] - before[p]));
    }
    return worst;
  }
};

std::unique_ptr<RingClocksRig> ring_in_op() {
  auto rig = std::make_unique<RingClocksRig>();
  EXPECT_TRUE(rig->robot.status().ok());
  EXPECT_TRUE(rig->nics.status().ok());
  const Status up = rig->bus.bring_up(testing::fast_options());
  EXPECT_TRUE(up.ok()) << testing::describe_master_failure(rig->bus.master());
  if (!up.ok()) return rig;
  for (int i = 0; i < kSettleCycles; ++i) rig->cycle();
  EXPECT_EQ(rig->bus.master().state(), MasterState::op) << testing::describe_master_failure(rig->bus.master());
  return rig;
}

// What one cut and its repair did to the clocks.
struct CutFigures {
  std::uint32_t difference_after_break{0};  // max |0x092C| from 100 ms after the cut to the repair
  std::int64_t sync0_moved{0};              // largest move of a drive's SYNC0 edge, from the cut to the repair
  SlaveMask written{0};                     // slaves the ring copy gave the reference time
  RingState state_when_open{RingState::none};
  RingState state_when_repaired{RingState::none};
  std::uint32_t difference_after_repair{0};
  std::int64_t true_offset_after_repair{0};
  std::int64_t sync0_moved_at_repair{0};
};

// Cuts `cable`, steps the crystals to `crystal_ppm` from their configured deviation, runs the break,
// restores the cable and runs on.
CutFigures cut_and_repair(RingClocksRig& rig, std::size_t cable, double crystal_ppm) {
  CutFigures f;
  const std::array<std::int64_t, kSlaveCount> before = rig.offsets();
  EXPECT_TRUE(rig.cut(cable).ok()) << cable;
  rig.step_crystals(crystal_ppm);
  for (int i = 0; i < kCyclesPerStep; ++i) {
    rig.cycle();
    f.sync0_moved = std::max(f.sync0_moved, rig.sync0_move(before));
    if (i >= kCyclesWithin) f.difference_after_break = std::max(f.difference_after_break, rig.max_difference());
  }
  const Master& master = rig.bus.master();
  f.state_when_open = master.ring_status().state;
  f.written = master.ring_dc_status().written;
  EXPECT_TRUE(rig.restore(cable).ok()) << cable;
  for (int i = 0; i < kCyclesAfterRepair; ++i) {
    rig.cycle();
    f.sync0_moved_at_repair = std::max(f.sync0_moved_at_repair, rig.sync0_move(before));
  }
  f.state_when_repaired = master.ring_status().state;
  f.difference_after_repair = rig.max_difference();
  f.true_offset_after_repair = rig.true_max_offset();
  std::printf("cable %2zu, crystals %+.0f ppm: after break max |0x092C| %u ns (from %d ms), SYNC0 moved %lld ns; "
              "after repair %u ns, true max offset %lld ns, SYNC0 moved %lld ns\n",
              cable, crystal_ppm, f.difference_after_break, kCyclesWithin, static_cast<long long>(f.sync0_moved),
              f.difference_after_repair, static_cast<long long>(f.true_offset_after_repair),
              static_cast<long long>(f.sync0_moved_at_repair));
  return f;
}

void expect_break_figures(const CutFigures& f, std::size_t cable) {
  EXPECT_EQ(f.state_when_open, RingState::open) << "cable " << cable;
  EXPECT_LE(f.difference_after_break, kBreakDifferenceBoundNs) << "cable " << cable;
  EXPECT_LE(f.sync0_moved, kSync0MoveBoundNs) << "cable " << cable;
  EXPECT_LE(f.sync0_moved_at_repair, kSync0MoveBoundNs) << "cable " << cable;
  EXPECT_EQ(f.state_when_repaired, RingState::closed) << "cable " << cable;
  // Behind every break but the ring cable's lie slaves: the ring copy gave them the reference time.
  if (cable < kRingCable) {
    EXPECT_NE(f.written, 0U) << "cable " << cable;
  }
}

TEST(RingClocks, EveryCableCutKeepsEveryClockAndTheRepairRestoresTheNoFaultBounds) {
  auto rig = ring_in_op();
  ASSERT_EQ(rig->bus.master().state(), MasterState::op);
  const std::uint32_t no_fault_difference = rig->max_difference();
  const std::int64_t no_fault_true_offset = rig->true_max_offset();
  std::printf("no fault: max |0x092C| %u ns, true max offset %lld ns\n", no_fault_difference,
              static_cast<long long>(no_fault_true_offset));
  for (std::size_t cable = 0; cable <= kRingCable; ++cable) {
    const CutFigures f = cut_and_repair(*rig, cable, 0.0);
    expect_break_figures(f, cable);
    EXPECT_LE(f.difference_after_repair, no_fault_difference + 2) << "cable " << cable;
    EXPECT_LE(f.true_offset_after_repair, no_fault_true_offset + 10) << "cable " << cable;
  }
}

// The drift loops behind a break run on (the clocks do not merely coast): at each cut every crystal
// but the reference's moves by 3 ppm (up at even cables, back at odd ones), which a clock whose loop
// stopped turns into 600 ns of SYNC0 movement over the 200 ms break.
TEST(RingClocks, TheDriftLoopsBehindEveryBreakFollowACrystalStep) {
  auto rig = ring_in_op();
  ASSERT_EQ(rig->bus.master().state(), MasterState::op);
  for (std::size_t cable = 0; cable <= kRingCable; ++cable) {
    const CutFigures f = cut_and_repair(*rig, cable, cable % 2 == 0 ? kCrystalStepPpm : 0.0);
    expect_break_figures(f, cable);
    EXPECT_LE(f.sync0_moved, kLoopFollowsBoundNs) << "cable " << cable << ": the drift loops did not follow the crystals";
    EXPECT_LE(f.difference_after_repair, kBreakDifferenceBoundNs) << "cable " << cable;
  }
}

}  // namespace
}  // namespace rescue::ecat
