#include "drivers/joint/joint_units.hpp"

#include <cmath>
#include <limits>

namespace rescue::drivers {
namespace {

template <typename Int>
Int saturate(double value) noexcept {
  const double v = std::nearbyint(value);
  if (!(v > static_cast<double>(std::numeric_limits<Int>::min()))) return std::numeric_limits<Int>::min();  // NaN too
  if (v >= static_cast<double>(std::numeric_limits<Int>::max())) return std::numeric_limits<Int>::max();
  return static_cast<Int>(v);
}

}  // namespace

std::int32_t rad_to_counts(double rad) noexcept { return saturate<std::int32_t>(rad * kCountsPerRad); }

std::int16_t nm_to_per_mille(double nm, const JointInfo& joint) noexcept {
  return saturate<std::int16_t>(nm * kPerMille / joint.rated_torque_nm);
}

}  // namespace rescue::drivers
