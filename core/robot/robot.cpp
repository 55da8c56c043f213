#include "core/robot/robot.hpp"

#include <array>
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

Result<JointMask> parse_joint_names(const char* list) noexcept {
  if (list == nullptr || list[0] == '\0') return make_error(Errc::invalid_argument, "empty list of joint names");
  JointMask mask = 0;
  std::uint32_t item = 0;
  const char* begin = list;
  for (;;) {
    ++item;
    const char* end = std::strchr(begin, ',');
    const std::size_t length = end != nullptr ? static_cast<std::size_t>(end - begin) : std::strlen(begin);
    if (length == 0) return make_error(Errc::invalid_argument, "empty joint name in the list", item);
    // A bounded copy of the item, so the table lookup is the one joint_index_by_name does.
    std::size_t joint = kJointCount;
    if (length <= kMaxJointNameLength) {
      std::array<char, kMaxJointNameLength + 1> name{};
      for (std::size_t i = 0; i < length; ++i) name[i] = begin[i];  // name[length] stays '\0'
      joint = joint_index_by_name(name.data());
    }
    if (joint == kJointCount) return make_error(Errc::invalid_argument, "unknown joint name in the list", item);
    mask |= joint_bit(joint);
    if (end == nullptr) return mask;
    begin = end + 1;
  }
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

}  // namespace rescue
