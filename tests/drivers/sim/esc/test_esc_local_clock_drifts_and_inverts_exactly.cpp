// The ESC's local clock: runs at its crystal's rate, takes speed and bounded phase corrections,
// and its inverse (the segment time at which a local time is reached) is exact to the nanosecond.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "drivers/sim/esc/esc_clock.hpp"

namespace rescue::drivers {
namespace {

TEST(EscLocalClock, RunsAtItsCrystalsDrift) {
  EscLocalClock c;
  c.reset(0, 5'000, 100.0);
  EXPECT_EQ(c.local_at(hal::kNsPerSec), 5'000 + hal::kNsPerSec + 100'000);  // +100 ppm: 100 us per second
  c.reset(0, 0, -100.0);
  EXPECT_EQ(c.local_at(hal::kNsPerSec), static_cast<std::uint64_t>(hal::kNsPerSec - 100'000));
}

TEST(EscLocalClock, PhaseCorrectionIsBoundedAndThenStops) {
  EscLocalClock c;
  c.reset(0, 0, 0.0);
  c.set_phase_correction(50.0, 1e-4);  // add 50 ns at 100 ppm: done after 500 us
  EXPECT_EQ(c.local_at(250'000), 250'025u);
  EXPECT_EQ(c.local_at(500'000), 500'050u);
  EXPECT_EQ(c.local_at(900'000), 900'050u);
  c.advance(900'000);
  EXPECT_EQ(c.phase_budget(), 0.0);
  EXPECT_EQ(c.local_at(1'000'000), 1'000'050u);
}

TEST(EscLocalClock, SpeedCorrectionCancelsDrift) {
  EscLocalClock c;
  c.reset(0, 0, 80.0);
  c.set_speed_correction(1.0 / (1.0 + 80e-6) - 1.0);
  EXPECT_NEAR(static_cast<double>(c.local_at(10 * hal::kNsPerSec)), 10e9, 1.0);
}

TEST(EscLocalClock, InverseFindsTheFirstNanosecondReachingALocalTime) {
  EscLocalClock c;
  c.reset(1'000, 123'456'789, 37.5);
  c.advance(2'000'000);
  c.set_speed_correction(-2.5e-5);
  c.set_phase_correction(-300.0, 2e-4);
  for (std::uint64_t target = c.local_at(2'000'000) + 1; target < c.local_at(2'000'000) + 5'000'000; target += 99'991) {
    const hal::Nanoseconds t = c.time_of_local(target);
    EXPECT_GE(c.local_at(t), target);
    EXPECT_LT(c.local_at(t - 1), target);
  }
}

TEST(EscLocalClock, ALocalTimeBeyondTheSegmentsRangeIsNeverReached) {
  // A start time the master wrote decades ahead (or one that wrapped round): found by the segment
  // fuzzer as an unrepresentable double-to-integer conversion.
  EscLocalClock c;
  c.reset(0, 1'000, 100.0);
  c.advance(5'000'000);
  EXPECT_EQ(c.time_of_local(std::numeric_limits<std::uint64_t>::max()), EscLocalClock::kNever);
  EXPECT_EQ(c.time_of_local(std::uint64_t{1} << 63), EscLocalClock::kNever);
  const std::uint64_t soon = c.local_at(5'000'000) + 1'000;
  EXPECT_LT(c.time_of_local(soon), 5'002'000);
}

TEST(EscLocalClock, AdvancingInStepsEqualsOneStep) {
  EscLocalClock a;
  EscLocalClock b;
  a.reset(0, 0, -63.0);
  b.reset(0, 0, -63.0);
  a.set_phase_correction(1000.0, 5e-4);
  b.set_phase_correction(1000.0, 5e-4);
  for (hal::Nanoseconds t = 0; t <= 10'000'000; t += 997) a.advance(t);
  b.advance(10'000'000 - (10'000'000 % 997));
  EXPECT_LE(a.local_at(10'000'000) > b.local_at(10'000'000) ? a.local_at(10'000'000) - b.local_at(10'000'000)
                                                           : b.local_at(10'000'000) - a.local_at(10'000'000),
            1u);
}

}  // namespace
}  // namespace rescue::drivers
