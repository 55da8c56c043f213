#include "core/app/tasks/predefined_messages.hpp"

namespace rescue::app {
namespace {

void add(JointCommandSequence& sequence, JointMask joints, fsm::JointInput input, ControlMode mode,
         JointCommandKind kind = JointCommandKind::dfa_input) noexcept {
  if (joints == 0) return;
  // Capacity is sized for the longest sequence this file builds.
  const bool added = sequence.push_back(JointCommand{joints, input, mode, kind});
  (void)added;
}

}  // namespace

JointCommandSequence initialize_robot_commands(JointMask joints) noexcept {
  JointCommandSequence sequence;
  for (const ControlMode mode :
       {ControlMode::cyclic_position, ControlMode::cyclic_velocity, ControlMode::cyclic_torque}) {
    JointMask of_mode = 0;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((joints & joint_bit(j)) != 0 && kJoints[j].default_mode == mode) of_mode |= joint_bit(j);
    }
    add(sequence, of_mode, fsm::JointInput::select_mode, mode);
  }
  add(sequence, joints, fsm::JointInput::set_reference, ControlMode::none);
  add(sequence, joints, fsm::JointInput::enable, ControlMode::none);
  return sequence;
}

JointCommandSequence stop_robot_commands(JointMask joints) noexcept {
  JointCommandSequence sequence;
  add(sequence, joints, fsm::JointInput::disable, ControlMode::none);
  return sequence;
}

JointCommandSequence clear_repaired_joints_commands(JointMask joints, bool confirm_moved) noexcept {
  JointCommandSequence sequence;
  // `input` is not read for a clear_lost command.
  add(sequence, joints, fsm::JointInput::reset, ControlMode::none,
      confirm_moved ? JointCommandKind::clear_lost_moved : JointCommandKind::clear_lost);
  add(sequence, joints, fsm::JointInput::reset, ControlMode::none);
  return sequence;
}

}  // namespace rescue::app
