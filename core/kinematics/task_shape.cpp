#include "core/kinematics/task_shape.hpp"

namespace rescue::kin {

JointMask arm_ik_joints(int arm) noexcept {
  JointMask mask = 0;
  // kIkJoints: the waist, then six left arm joints, then six right arm joints.
  for (std::size_t c = 1 + 6 * static_cast<std::size_t>(arm); c < 7 + 6 * static_cast<std::size_t>(arm); ++c) {
    mask |= joint_bit(kIkJoints[c]);
  }
  return mask;
}

TaskShape task_shape_for(JointMask out_of_service) noexcept {
  TaskShape shape;
  for (int arm = 0; arm < 2; ++arm) {
    const JointMask joints = arm_ik_joints(arm);
    if ((out_of_service & joints) == 0) continue;
    shape.palm_active[static_cast<std::size_t>(arm)] = false;
    shape.held |= joints;
    shape.held |= joint_bit(kIkJoints[0]);  // the waist
  }
  shape.held &= ~out_of_service;
  return shape;
}

}  // namespace rescue::kin
