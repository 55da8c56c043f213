#include "core/robot.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

namespace rescue {

const char* to_string(Branch branch) noexcept {
  switch (branch) {
    case Branch::torso: return "torso";
    case Branch::left_arm: return "left_arm";
    case Branch::right_arm: return "right_arm";
    case Branch::lower_body: return "lower_body";
  }
  return "unknown";
}

std::size_t joint_index_by_name(const char* name) noexcept {
  if (name == nullptr) return kJointCount;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (std::strcmp(kJoints[j].name, name) == 0) return j;
  }
  return kJointCount;
}

void format_joint_names(JointMask mask, char* out, std::size_t capacity) noexcept {
  if (capacity == 0) return;
  std::size_t used = 0;
  out[0] = '\0';
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((mask & joint_bit(j)) == 0 || used >= capacity) continue;
    const int n = std::snprintf(out + used, capacity - used, "%s%s", used == 0 ? "" : ",", kJoints[j].name);
    if (n < 0) return;
    used += static_cast<std::size_t>(n);
  }
  if (used == 0) (void)std::snprintf(out, capacity, "none");
}

std::int32_t rad_to_counts(double rad) noexcept {
  const double counts = std::nearbyint(rad * kCountsPerRad);
  if (!(counts > static_cast<double>(std::numeric_limits<std::int32_t>::min()))) {
    return std::numeric_limits<std::int32_t>::min();
  }
  if (counts >= static_cast<double>(std::numeric_limits<std::int32_t>::max())) {
    return std::numeric_limits<std::int32_t>::max();
  }
  return static_cast<std::int32_t>(counts);
}

}  // namespace rescue
