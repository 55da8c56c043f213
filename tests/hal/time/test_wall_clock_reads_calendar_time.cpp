#include <gtest/gtest.h>

#include "hal/time/wall_clock.hpp"

namespace rescue::hal {
namespace {

TEST(WallClock, SystemClockIsUnixTime) {
  SystemWallClock clock;
  EXPECT_GT(clock.unix_time_ns(), 1'600'000'000LL * 1'000'000'000LL);  // after September 2020
}

TEST(WallClock, ManualClockHoldsWhatItIsSet) {
  ManualWallClock clock(42);
  EXPECT_EQ(clock.unix_time_ns(), 42);
  clock.set(-7);
  EXPECT_EQ(clock.unix_time_ns(), -7);
}

}  // namespace
}  // namespace rescue::hal
