// sin and cos of one angle together, inline and branch-light: the joint angles of every FK. Range
// reduction by the quadrant (pi/2 split in three parts, Cody-Waite), then the Taylor series of sin
// and cos on [-pi/4, pi/4] to degree 17/18, whose truncation error (< 1e-17) is below rounding.
// Within a few ulp of libm for |x| < 1e6 (tests/core/kinematics/test_sincos_matches_libm);
// larger angles (a continuous track after kilometres) go to libm.
#pragma once

#include <cmath>
#include <cstdint>

namespace rescue::kin {

struct SinCos {
  double s;
  double c;
};

inline SinCos sincos(double x) noexcept {
  if (!(std::fabs(x) < 1e6)) return {std::sin(x), std::cos(x)};
  constexpr double kTwoOverPi = 0.63661977236758134308;
  // pi/2 = kP1 + kP2 to ~1e-27; kP1 has 33 significant bits, so k * kP1 is exact for |k| < 2^20
  // and x - k * kP1 loses nothing; k * kP2 is rounded far below the result's ulp.
  constexpr double kP1 = 1.5707963267341256e+00;
  constexpr double kP2 = 6.0771005065061922e-11;
  const double k = std::nearbyint(x * kTwoOverPi);
  const double r = (x - k * kP1) - k * kP2;
  const double r2 = r * r;
  // sin r = r (1 - r2/3! + r2^2/5! - ...), cos r = 1 - r2/2! + r2^2/4! - ...
  const double sp = 1.0 + r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880 +
                    r2 * (-1.0 / 39916800 + r2 * (1.0 / 6227020800 + r2 * (-1.0 / 1307674368000 +
                    r2 * (1.0 / 355687428096000))))))));
  const double cp = 1.0 + r2 * (-1.0 / 2 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 +
                    r2 * (-1.0 / 3628800 + r2 * (1.0 / 479001600 + r2 * (-1.0 / 87178291200 +
                    r2 * (1.0 / 20922789888000 + r2 * (-1.0 / 6402373705728000)))))))));
  const double s = r * sp;
  switch (static_cast<std::int64_t>(k) & 3) {
    case 0: return {s, cp};
    case 1: return {cp, -s};
    case 2: return {-s, -cp};
    default: return {-cp, s};
  }
}

}  // namespace rescue::kin
