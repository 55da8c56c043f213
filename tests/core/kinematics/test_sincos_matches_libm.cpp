// The FK's inline sincos agrees with libm's sin and cos to a few ulp over joint angles and far
// beyond (continuous tracks), and hands huge or non-finite angles to libm.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/kinematics/sincos.hpp"

namespace rescue::kin {
namespace {

TEST(Sincos, MatchesLibmOverJointAnglesAndTrackTurns) {
  std::mt19937_64 rng(31);
  double worst = 0.0;
  for (const double range : {4.0, 100.0, 1e5}) {
    std::uniform_real_distribution<double> angle(-range, range);
    for (int n = 0; n < 200000; ++n) {
      const double x = angle(rng);
      const SinCos sc = sincos(x);
      worst = std::max({worst, std::fabs(sc.s - std::sin(x)), std::fabs(sc.c - std::cos(x))});
    }
  }
  EXPECT_LT(worst, 4e-16) << "worst " << worst;
}

TEST(Sincos, ExactAtQuadrantsAndDelegatesOutsideItsRange) {
  EXPECT_EQ(sincos(0.0).s, 0.0);
  EXPECT_EQ(sincos(0.0).c, 1.0);
  EXPECT_NEAR(sincos(M_PI / 2).s, 1.0, 1e-16);
  EXPECT_NEAR(sincos(-M_PI).c, -1.0, 1e-16);
  EXPECT_EQ(sincos(3e7).s, std::sin(3e7));
  EXPECT_TRUE(std::isnan(sincos(std::numeric_limits<double>::quiet_NaN()).s));
  EXPECT_TRUE(std::isnan(sincos(std::numeric_limits<double>::infinity()).c));
}

}  // namespace
}  // namespace rescue::kin
