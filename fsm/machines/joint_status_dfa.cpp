#include "fsm/machines/joint_status_dfa.hpp"

#include <cstring>

namespace rescue::fsm {

const char* to_string(JointState state) noexcept { return JointStatusMachine::state_name(state); }
const char* to_string(JointInput input) noexcept { return JointStatusMachine::input_name(input); }

bool parse_joint_input(const char* name, JointInput& out) noexcept {
  if (name == nullptr) return false;
  for (const auto& spec : JointStatusDfa::kInputs) {
    if (std::strcmp(spec.name, name) == 0) {
      out = spec.input;
      return true;
    }
  }
  return false;
}

const char* to_string(RobotCondition condition) noexcept {
  switch (condition) {
    case RobotCondition::idle: return "idle";
    case RobotCondition::configured: return "configured";
    case RobotCondition::ready: return "ready";
    case RobotCondition::enabled: return "enabled";
    case RobotCondition::degraded: return "degraded";
    case RobotCondition::error: return "error";
  }
  return "unknown";
}

RobotStatusSummary summarize(const std::array<JointState, kJointCount>& states) noexcept {
  RobotStatusSummary summary;
  for (std::size_t j = 0; j < kJointCount; ++j) summary.joints_in[index_of(states[j])] |= joint_bit(j);
  const JointMask in_error = summary.joints_in[index_of(JointState::error)];
  summary.usable = kAllJoints & ~in_error;
  if (in_error == kAllJoints) {
    summary.condition = RobotCondition::error;
  } else if (in_error != 0) {
    summary.condition = RobotCondition::degraded;
  } else if (summary.joints_in[index_of(JointState::idle)] == kAllJoints) {
    summary.condition = RobotCondition::idle;
  } else if (summary.joints_in[index_of(JointState::enabled)] == kAllJoints) {
    summary.condition = RobotCondition::enabled;
  } else if ((summary.joints_in[index_of(JointState::idle)] | summary.joints_in[index_of(JointState::configured)]) != 0) {
    // Mixed, with some joints still Idle or Configured: the robot as a whole is being configured.
    summary.condition = RobotCondition::configured;
  } else {
    summary.condition = RobotCondition::ready;  // every joint Ready or Enabled
  }
  return summary;
}

}  // namespace rescue::fsm
