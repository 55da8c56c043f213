// Pre-defined user messages of the message parser (paper III-B): one operator message that the
// parser splits into the joint setting steps the joint status DFA takes one at a time.
//
//   "initialize robot"  -> select_mode (each joint's default mode) -> set_reference -> enable
//   "stop robot"        -> disable
//   "clear repaired"    -> clear_lost (operator: the joints were repaired) -> reset (Error -> Idle);
//                          clear_lost_moved instead when the operator also confirms joints that
//                          returned away from their held position (ctl clear JOINTS --moved)
//
// The joint manager applies the commands in order; a joint that cannot take a step (lost, in
// Error) refuses it and the refusal is counted and logged there, the others go on.
#pragma once

#include "core/app/links/joint_messages.hpp"
#include "core/containers/fixed_vector.hpp"
#include "core/robot/robot.hpp"

namespace rescue::app {

// At most one select_mode per control mode, then set_reference and enable.
constexpr std::size_t kMaxInitializeSteps = kMaxRequestSteps;
using JointCommandSequence = FixedVector<JointCommand, kMaxInitializeSteps>;

JointCommandSequence initialize_robot_commands(JointMask joints) noexcept;
JointCommandSequence stop_robot_commands(JointMask joints) noexcept;
JointCommandSequence clear_repaired_joints_commands(JointMask joints, bool confirm_moved = false) noexcept;

}  // namespace rescue::app
