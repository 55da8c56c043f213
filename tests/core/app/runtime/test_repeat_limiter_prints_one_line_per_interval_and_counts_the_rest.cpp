// The supervisor's repeated warnings rate-limited (issue 36 item 11; core/app/runtime/repeat_limiter.hpp):
// per task, the first line is printed (whole), then at most one per interval; the occurrences in
// between are counted and handed to the next printed line. Virtual time: the times are passed in.
#include <gtest/gtest.h>

#include "core/app/runtime/repeat_limiter.hpp"

namespace rescue::app {
namespace {

constexpr hal::Nanoseconds kInterval = 10 * hal::kNsPerSec;

TEST(RepeatLimiter, TheFirstLineIsPrintedWhole) {
  RepeatLimiter<2> limiter(kInterval);
  const auto first = limiter.admit(0, 5 * hal::kNsPerSec);
  EXPECT_TRUE(first.print);
  EXPECT_TRUE(first.first);
  EXPECT_EQ(first.suppressed, 0U);
}

TEST(RepeatLimiter, RepeatsWithinTheIntervalAreCountedAndTheNextLineSaysHowMany) {
  RepeatLimiter<2> limiter(kInterval);
  ASSERT_TRUE(limiter.admit(0, 0).print);
  // 1 500 silences in the next 9.9 s: none printed, all counted.
  for (int i = 1; i <= 1500; ++i) {
    EXPECT_FALSE(limiter.admit(0, i * 6'600'000LL).print);
  }
  EXPECT_EQ(limiter.pending(0), 1500U);
  EXPECT_EQ(limiter.suppressed_total(), 1500U);
  // The interval passed: the next one is printed, not as the first, with the 1 500 left out.
  const auto next = limiter.admit(0, kInterval);
  EXPECT_TRUE(next.print);
  EXPECT_FALSE(next.first);
  EXPECT_EQ(next.suppressed, 1500U);
  EXPECT_EQ(limiter.pending(0), 0U);
  EXPECT_EQ(limiter.suppressed_total(), 1500U);
  // The interval counts from that printed line.
  EXPECT_FALSE(limiter.admit(0, kInterval + kInterval - 1).print);
  EXPECT_EQ(limiter.pending(0), 1U);
}

TEST(RepeatLimiter, EachKeyHasItsOwnInterval) {
  RepeatLimiter<2> limiter(kInterval);
  ASSERT_TRUE(limiter.admit(0, 0).print);
  EXPECT_FALSE(limiter.admit(0, 1).print);
  // Another task's first silence is printed at once, whole.
  const auto other = limiter.admit(1, 2);
  EXPECT_TRUE(other.print);
  EXPECT_TRUE(other.first);
  EXPECT_EQ(other.suppressed, 0U);
  EXPECT_EQ(limiter.pending(0), 1U);
  EXPECT_EQ(limiter.pending(1), 0U);
  EXPECT_EQ(limiter.suppressed_total(), 1U);
}

}  // namespace
}  // namespace rescue::app
