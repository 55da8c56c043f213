// The master's wake-up PI controller against a reference clock running 100 ppm fast or slow:
// the frame's phase in the SYNC0 period converges to the target and stays there (no slow drift
// between the master's clock and the network's), and the first wake-up starts on target.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <cstdlib>

#include "ecat/dc/dc_cycle_sync.hpp"

namespace rescue::ecat {
namespace {

constexpr hal::Nanoseconds kCycle = hal::kNsPerMs;

struct Reference {
  double rate;          // system-time ns per master ns
  std::uint64_t at_zero;
  std::uint64_t at(hal::Nanoseconds master) const {
    return at_zero + static_cast<std::uint64_t>(std::llround(static_cast<double>(master) * rate));
  }
};

hal::Nanoseconds run(double ppm, int cycles, hal::Nanoseconds* worst_after_settling) {
  const Reference ref{1.0 + ppm * 1e-6, 0x0000123456789000ULL};
  const std::uint64_t sync0_start = ref.at(5 * kCycle) / kCycle * kCycle;
  DcCycleSync sync(kCycle, sync0_start, kCycle / 2);
  const hal::Nanoseconds transit = 3'000;  // send to passing the reference
  hal::Nanoseconds wake = sync.first_wakeup(10 * kCycle, 0, ref.at(0));
  hal::Nanoseconds worst = 0;
  for (int k = 0; k < cycles; ++k) {
    const hal::Nanoseconds shift = sync.update(ref.at(wake + transit));
    if (k > 300) worst = std::max(worst, std::abs(sync.last_error()));
    wake += kCycle + shift;
  }
  *worst_after_settling = worst;
  return sync.last_error();
}

TEST(DcCycleSync, HoldsThePhaseWithTheReference100PpmFast) {
  hal::Nanoseconds worst = 0;
  const hal::Nanoseconds last = run(+100.0, 100'000, &worst);  // 100 s of cycles
  EXPECT_LE(std::abs(last), 2);
  EXPECT_LE(worst, 10);
}

TEST(DcCycleSync, HoldsThePhaseWithTheReference100PpmSlow) {
  hal::Nanoseconds worst = 0;
  const hal::Nanoseconds last = run(-100.0, 100'000, &worst);
  EXPECT_LE(std::abs(last), 2);
  EXPECT_LE(worst, 10);
}

TEST(DcCycleSync, WithoutCorrectionTheMasterWouldDriftAway) {
  // What the controller prevents: 100 ppm is a full period of drift in 10 s.
  const Reference ref{1.0 + 100e-6, 0};
  DcCycleSync sync(kCycle, 0, kCycle / 2);
  const hal::Nanoseconds e0 = sync.phase_error(ref.at(kCycle / 2));
  const hal::Nanoseconds e1 = sync.phase_error(ref.at(kCycle / 2 + 2'500 * kCycle));
  EXPECT_NEAR(static_cast<double>(e1 - e0), 250'000.0, 1.0);
}

TEST(DcCycleSync, FirstWakeupLandsOnTheTargetPhase) {
  const std::uint64_t s0 = 7'000'000'000ULL;
  DcCycleSync sync(kCycle, s0, kCycle / 2);
  // Reference read 5'123'456 ns ahead of the master clock.
  const hal::Nanoseconds now = 1'000'000'777;
  const hal::Nanoseconds wake = sync.first_wakeup(now, now, static_cast<std::uint64_t>(now) + 5'123'456);
  EXPECT_GT(wake, now);
  EXPECT_LE(wake, now + kCycle);
  EXPECT_EQ(sync.phase_error(static_cast<std::uint64_t>(wake) + 5'123'456), 0);
}

TEST(DcCycleSync, PhaseErrorWrapsIntoHalfAPeriod) {
  DcCycleSync sync(kCycle, 0, kCycle / 2);
  EXPECT_EQ(sync.phase_error(kCycle / 2 + 10), 10);
  EXPECT_EQ(sync.phase_error(kCycle / 2 - 10), -10);
  EXPECT_EQ(sync.phase_error(kCycle / 2 + kCycle * 7 + 499'999), 499'999);
  EXPECT_EQ(sync.phase_error(kCycle / 2 + 500'000), -500'000);
}

}  // namespace
}  // namespace rescue::ecat
