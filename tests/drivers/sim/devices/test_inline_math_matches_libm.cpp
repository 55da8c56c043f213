// drivers/sim/devices/inline_math.hpp gives, bit for bit, what libm gives: the simulator's frames depend on
// it. Edge values (signed zeros, halves, the ends of the exact range, infinities, NaN) and a
// million values spread over the magnitudes the simulator uses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "drivers/sim/devices/inline_math.hpp"

namespace rescue::drivers {
namespace {

namespace im = inline_math;

std::uint64_t bits(double v) {
  std::uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

std::vector<double> edge_values() {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> v = {0.0, -0.0, 0.3, -0.3, 0.5, -0.5, 0.49999999999999994, -0.49999999999999994, 1.0, -1.0,
                           1.5, -1.5, 2.5, -2.5, 3.5, -3.5, 1e-300, -1e-300, 4503599627370495.5, -4503599627370495.5,
                           4503599627370496.0, -4503599627370496.0, 4503599627370497.0, 9007199254740993.0, 1e18, -1e18,
                           inf, -inf, std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max()};
  for (double x = -5.0; x <= 5.0; x += 0.125) v.push_back(x);
  return v;
}

std::vector<double> spread_values() {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 60);
  std::vector<double> v;
  for (int i = 0; i < 1'000'000; ++i) v.push_back(std::ldexp(unit(random), exponent(random)));
  return v;
}

TEST(InlineMath, FloorCeilAndNearbyintAreLibmsBitForBit) {
  for (const auto& values : {edge_values(), spread_values()}) {
    for (const double x : values) {
      ASSERT_EQ(bits(im::floor(x)), bits(std::floor(x))) << x;
      ASSERT_EQ(bits(im::ceil(x)), bits(std::ceil(x))) << x;
      ASSERT_EQ(bits(im::nearbyint(x)), bits(std::nearbyint(x))) << x;
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(im::floor(nan)));
  EXPECT_TRUE(std::isnan(im::ceil(nan)));
  EXPECT_TRUE(std::isnan(im::nearbyint(nan)));
}

TEST(InlineMath, LlroundIsLibmsInsideTheInt64Range) {
  for (const auto& values : {edge_values(), spread_values()}) {
    for (const double x : values) {
      if (!(std::fabs(x) < 9.2e18)) continue;
      ASSERT_EQ(im::llround(x), std::llround(x)) << x;
    }
  }
}

TEST(InlineMath, FminIsLibmsForMagnitudesAndNan) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> values = spread_values();
  for (std::size_t i = 0; i + 1 < values.size(); i += 2) {
    const double a = std::fabs(values[i]);
    const double b = std::fabs(values[i + 1]);
    ASSERT_EQ(bits(im::fmin(a, b)), bits(std::fmin(a, b))) << a << " " << b;
    ASSERT_EQ(bits(im::fmin(a, a)), bits(std::fmin(a, a))) << a;
  }
  EXPECT_EQ(im::fmin(nan, 2.0), 2.0);
  EXPECT_EQ(im::fmin(2.0, nan), 2.0);
  EXPECT_EQ(bits(im::fmin(0.0, 0.0)), bits(0.0));
  EXPECT_EQ(im::fmin(std::numeric_limits<double>::infinity(), 3.0), 3.0);
}

}  // namespace
}  // namespace rescue::drivers
