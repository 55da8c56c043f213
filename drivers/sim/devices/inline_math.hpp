// libm's floor, ceil, fmin, nearbyint and llround, inline and bit for bit the same.
//
// Why: on the baseline x86-64 target (no SSE4.1 rounding instructions) these are library calls
// through the PLT, and the simulator makes some hundred of them per simulated cycle (local clocks,
// DC registers, encoders). Their results feed the simulated robot's frames, which must not change
// (tests/drivers/sim/segment/test_simulated_robot_replays_the_recorded_digest.cpp), so these are exact:
// tests/drivers/sim/devices/test_inline_math_matches_libm.cpp compares them with libm, signed zeros, halves,
// infinities and NaN included. The rounding mode is the default one (the program never changes it).
#pragma once

#include <cmath>
#include <cstdint>

namespace rescue::drivers::inline_math {

// From 2^52 on, every double is an integer.
constexpr double kIntegral = 4503599627370496.0;

inline double floor(double x) noexcept {
  if (!(std::fabs(x) < kIntegral)) return x;  // integral, infinite or NaN: floor(x) is x
  const auto t = static_cast<double>(static_cast<std::int64_t>(x));  // toward zero, exact here
  return t > x ? t - 1.0 : std::copysign(t, x);  // copysign: floor(-0.0) is -0.0
}

inline double ceil(double x) noexcept {
  if (!(std::fabs(x) < kIntegral)) return x;
  const auto t = static_cast<double>(static_cast<std::int64_t>(x));
  return t < x ? t + 1.0 : std::copysign(t, x);  // copysign: ceil(-0.3) is -0.0
}

// std::fmin: the other operand when one is NaN. Both operands zero of different signs is the one
// case left to the implementation; callers pass magnitudes (never -0.0).
inline double fmin(double x, double y) noexcept { return (y < x || x != x) ? y : x; }

// std::nearbyint in the default rounding mode: to nearest, ties to even. Adding 2^52 to a
// magnitude below it rounds exactly there (the spacing of doubles is 1); subtracting is exact.
inline double nearbyint(double x) noexcept {
  const double magnitude = std::fabs(x);
  if (!(magnitude < kIntegral)) return x;
  // Not folded away: compilers keep IEEE arithmetic as written unless told otherwise (-ffast-math).
  return std::copysign((magnitude + kIntegral) - kIntegral, x);
}

// std::llround for |x| < 2^63 (and no NaN): to nearest, ties away from zero. x - trunc(x) is
// exact, so the comparison with one half is too. Without branches: which way a measured value
// rounds is a coin toss, and a mispredicted branch at the end of a long division/square-root chain
// costs more than the arithmetic.
inline std::int64_t llround(double x) noexcept {
  const auto i = static_cast<std::int64_t>(x);
  const double remainder = x - static_cast<double>(i);
  return i + static_cast<std::int64_t>(remainder >= 0.5) - static_cast<std::int64_t>(remainder <= -0.5);
}

}  // namespace rescue::drivers::inline_math
