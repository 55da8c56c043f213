// sin and cos of one angle together, inline and branch-light: the joint angles of every FK. Range
// reduction by the quadrant (pi/2 split in three parts, Cody-Waite), then the Taylor series of sin
// and cos on [-pi/4, pi/4] to degree 17/18, whose truncation error (< 1e-17) is below rounding.
// Within a few ulp of libm for |x| < 1e6 (tests/core/kinematics/test_sincos_matches_libm);
// larger angles (a continuous track after kilometres) go to libm.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

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
  // Round to nearest by the 1.5 * 2^52 trick: no libm call (nearbyint is one without SSE4.1).
  constexpr double kRound = 6755399441055744.0;
  const double k = (x * kTwoOverPi + kRound) - kRound;
  const double r = (x - k * kP1) - k * kP2;
  // Taylor series to r^15 (sin) and r^16 (cos): the first omitted terms are below 5e-17 on
  // [-pi/4, pi/4]. Estrin's scheme (pairs, then powers r^4, r^8) instead of Horner's: the chain of
  // dependent operations is 4 deep instead of 8, which is most of the cost of a joint.
  const double z = r * r;
  const double z2 = z * z;
  const double z4 = z2 * z2;
  const double z8 = z4 * z4;
  const double s01 = 1.0 - z * (1.0 / 6);
  const double s23 = 1.0 / 120 - z * (1.0 / 5040);
  const double s45 = 1.0 / 362880 - z * (1.0 / 39916800);
  const double s67 = 1.0 / 6227020800 - z * (1.0 / 1307674368000);
  const double sp = (s01 + z2 * s23) + z4 * (s45 + z2 * s67);
  const double c01 = 1.0 - z * (1.0 / 2);
  const double c23 = 1.0 / 24 - z * (1.0 / 720);
  const double c45 = 1.0 / 40320 - z * (1.0 / 3628800);
  const double c67 = 1.0 / 479001600 - z * (1.0 / 87178291200);
  const double cp = ((c01 + z2 * c23) + z4 * (c45 + z2 * c67)) + z8 * (1.0 / 20922789888000);
  const double s = r * sp;
  // Quadrant without branches (random joint angles would mispredict a switch):
  // k mod 4 = 0: (s, c)  1: (c, -s)  2: (-s, -c)  3: (-c, s).
  // Selected and signed on the bits (a mask picks s or c, an XOR flips the sign bit): GCC turned the
  // former `odd ? cp : s` and `? -1.0 : 1.0` into jumps, which random joint angles mispredict about
  // half the time; that made FK's p99 40 % above its median (docs/kinematics.md). Bit for bit the
  // same results as the multiplication by +-1.
  const auto quadrant = static_cast<std::uint64_t>(static_cast<std::int64_t>(k));
  std::uint64_t s_bits = 0;
  std::uint64_t c_bits = 0;
  std::memcpy(&s_bits, &s, sizeof s_bits);
  std::memcpy(&c_bits, &cp, sizeof c_bits);
  const std::uint64_t odd_mask = std::uint64_t{0} - (quadrant & 1U);  // all ones when odd
  const std::uint64_t sin_bits = ((s_bits & ~odd_mask) | (c_bits & odd_mask)) ^ ((quadrant & 2U) << 62U);
  const std::uint64_t cos_bits = ((c_bits & ~odd_mask) | (s_bits & odd_mask)) ^ (((quadrant + 1U) & 2U) << 62U);
  SinCos out{};
  std::memcpy(&out.s, &sin_bits, sizeof out.s);
  std::memcpy(&out.c, &cos_bits, sizeof out.c);
  return out;
}

}  // namespace rescue::kin
