#include <gtest/gtest.h>

#include <cmath>

#include "hal/time/clock.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::hal {
namespace {

TEST(TscTimer, InvariantTscIsCpuidEdxBit8) {
  EXPECT_TRUE(invariant_tsc_bit(1U << 8U));
  EXPECT_TRUE(invariant_tsc_bit(0xFFFFFFFFU));
  EXPECT_FALSE(invariant_tsc_bit(0U));
  EXPECT_FALSE(invariant_tsc_bit(~(1U << 8U)));
}

TEST(TscTimer, RdtscpIsCpuidEdxBit27) {
  EXPECT_TRUE(rdtscp_bit(1U << 27U));
  EXPECT_FALSE(rdtscp_bit(~(1U << 27U)));
}

TEST(TscTimer, RatioOfTwoReadings) {
  EXPECT_DOUBLE_EQ(ticks_per_ns_between(1000, 0, 4000, 1000), 3.0);
  EXPECT_DOUBLE_EQ(ticks_per_ns_between(5, 10, 5, 20), 0.0);    // counter stood still
  EXPECT_DOUBLE_EQ(ticks_per_ns_between(10, 20, 20, 20), 0.0);  // no time passed
}

TEST(TscTimer, CalibratedTimerNeverRunsBackwardsAndConvertsByItsRatio) {
  const TscTimer timer = TscTimer::calibrate(2 * kNsPerMs);
  RecordProperty("source", to_string(timer.source()));
  RecordProperty("reason", timer.reason());
#if defined(__x86_64__)
  EXPECT_NE(timer.source(), TimerSource::arm_counter);
#endif
  ASSERT_GT(timer.ticks_per_ns(), 0.0);
  ASSERT_TRUE(std::isfinite(timer.ticks_per_ns()));
  for (int i = 0; i < 10'000; ++i) {
    const std::uint64_t start = timer.start();
    const std::uint64_t stop = timer.stop();
    ASSERT_GE(stop, start);
  }
  const auto one_ms_of_ticks = static_cast<std::uint64_t>(timer.ticks_per_ns() * 1e6);
  EXPECT_NEAR(static_cast<double>(timer.to_ns(one_ms_of_ticks)), 1e6, 1.0);
  EXPECT_EQ(timer.to_ns(0), 0);
}

TEST(TscTimer, FallbackCountsMonotonicNanoseconds) {
  const TscTimer timer = TscTimer::monotonic_fallback("forced by the test");
  EXPECT_EQ(timer.source(), TimerSource::clock_gettime);
  EXPECT_STREQ(timer.reason(), "forced by the test");
  EXPECT_DOUBLE_EQ(timer.ticks_per_ns(), 1.0);
  EXPECT_EQ(timer.to_ns(1234), 1234);
  MonotonicClock clock;
  const Nanoseconds before = clock.now();
  const std::uint64_t start = timer.start();
  const std::uint64_t stop = timer.stop();
  const Nanoseconds after = clock.now();
  EXPECT_LE(before, static_cast<Nanoseconds>(start));
  EXPECT_LE(start, stop);
  EXPECT_LE(static_cast<Nanoseconds>(stop), after);
}

TEST(TscTimer, EverySourceHasAName) {
  EXPECT_STREQ(to_string(TimerSource::tsc), "tsc");
  EXPECT_STREQ(to_string(TimerSource::arm_counter), "arm_counter");
  EXPECT_STREQ(to_string(TimerSource::clock_gettime), "clock_gettime");
}

}  // namespace
}  // namespace rescue::hal
