// A cycle that overruns, or a wake-up that comes late, makes the master skip whole periods to keep
// the phase with the DC reference: those periods have no cycle, so a 2 s run at 1 ms counts fewer
// than 2000 cycles. Master::skipped_periods() counts them (the run summary and `ctl master` add them
// to the late periods), so that cycles() + skipped_periods() is every period since the first cycle.
// The time between the bring-up and the first cycle of the periodic loop (forking the tasks) is
// start-up, not skipped periods: Master::realign_schedule() moves the first wake-up past it, in phase,
// without counting. Virtual time: the stalls are exact.
#include <gtest/gtest.h>

#include <memory>

#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

class SkippedPeriods : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = std::make_unique<SimulatedRobotRig>();
    options = testing::fast_options();
    ASSERT_TRUE(rig->bus.bring_up(options).ok());
    for (int i = 0; i < 200 && rig->bus.master().state() != MasterState::op; ++i) (void)cycle();
    ASSERT_EQ(rig->bus.master().state(), MasterState::op);
  }
  drivers::JointCycleResult cycle() { return rig->cycle(refs, feedback); }

  std::unique_ptr<SimulatedRobotRig> rig;
  MasterOptions options{};
  drivers::JointReferences refs{};
  drivers::JointFeedback feedback{};
};

TEST_F(SkippedPeriods, OnTimeCyclesSkipNothing) {
  for (int i = 0; i < 500; ++i) (void)cycle();
  EXPECT_EQ(rig->bus.master().skipped_periods(), 0U);
}

TEST_F(SkippedPeriods, AStallOfSeveralPeriodsIsCountedAndCyclesPlusSkippedCoverEveryPeriod) {
  const hal::Nanoseconds period = options.cycle_time;
  const std::uint64_t cycles_before = rig->bus.master().cycles();
  const hal::Nanoseconds first = rig->bus.next_wakeup();
  std::uint64_t expected_skipped = 0;
  for (int i = 0; i < 300; ++i) {
    if (i == 100 || i == 200) {
      // The host stalls 3.5 and then 7.2 periods past the wake-up: the cycle runs late, and the
      // periods that began meanwhile get no cycle of their own.
      const hal::Nanoseconds stall = i == 100 ? period * 7 / 2 : period * 36 / 5;
      rig->clock.sleep_until(rig->bus.next_wakeup() + stall);
      expected_skipped += static_cast<std::uint64_t>(stall / period);
    }
    (void)cycle();
  }
  const std::uint64_t cycles = rig->bus.master().cycles() - cycles_before;
  EXPECT_EQ(rig->bus.master().skipped_periods(), expected_skipped);
  // Every period from the first wake-up to the next one is a cycle or a skipped period (the DC
  // loop's phase corrections are far below a period).
  const auto periods = static_cast<std::uint64_t>((rig->bus.next_wakeup() - first + period / 2) / period);
  EXPECT_EQ(cycles + rig->bus.master().skipped_periods(), periods);
}

TEST_F(SkippedPeriods, StartUpBeforeTheLoopIsRealignedNotCountedAsSkipped) {
  const hal::Nanoseconds period = options.cycle_time;
  const hal::Nanoseconds due = rig->bus.next_wakeup();
  const std::uint64_t skipped_before = rig->bus.master().skipped_periods();
  // The loop starts 114.3 periods after the next wake-up was due (the tasks were being started).
  rig->clock.sleep_until(due + period * 1143 / 10);
  rig->bus.master().realign_schedule();
  const hal::Nanoseconds realigned = rig->bus.next_wakeup();
  EXPECT_GT(realigned, rig->clock.now());
  EXPECT_LE(realigned - rig->clock.now(), period);
  EXPECT_EQ((realigned - due) % period, 0) << "same phase";
  for (int i = 0; i < 100; ++i) (void)cycle();
  EXPECT_EQ(rig->bus.master().skipped_periods(), skipped_before);
}

}  // namespace
}  // namespace rescue::ecat
