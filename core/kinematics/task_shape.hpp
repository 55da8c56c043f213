// What the rescue task still asks of the arms once joints are out of service (docs/kinematics.md
// "After damage"). The paper's reason for the architecture: a robot that does not recognise damage
// "may calculate incorrect motion behaviors while solving kinematics". So when the set of joints out
// of service changes, the task stack changes, not only the locked columns:
//   - an arm with any of its six IK joints out of service is damaged: its palm leaves the main task
//     (its target can no longer be tracked in every direction) and its healthy joints are held where
//     they are, braking to rest at their acceleration limit: they never drag an unpowered forearm
//     that may carry the person;
//   - with an arm damaged, the waist (the one joint both arms share) is held too: turning it would
//     swing the damaged arm and its load for no direction the healthy palm lacks (its six joints
//     move it in all six);
//   - the healthy arm keeps its palm on its path and finishes its part of the motion.
// Joints outside the IK (neck, hands, legs, tracks) change nothing here.
#pragma once

#include <array>

#include "core/kinematics/kinematic_model.hpp"

namespace rescue::kin {

struct TaskShape {
  JointMask held{0};                            // IK joints in service held (braking to rest)
  std::array<bool, 2> palm_active{{true, true}};  // 0 left, 1 right: the palm is in the main task
};

// The six IK joints of an arm (0 left, 1 right), the waist excluded.
JointMask arm_ik_joints(int arm) noexcept;

// The task stack for `out_of_service`.
TaskShape task_shape_for(JointMask out_of_service) noexcept;

}  // namespace rescue::kin
