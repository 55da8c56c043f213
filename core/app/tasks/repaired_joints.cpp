#include "core/app/tasks/repaired_joints.hpp"

namespace rescue::app {

RepairedJointsPlan plan_repaired_joints(JointMask requested, JointMask recorded_lost) noexcept {
  RepairedJointsPlan plan;
  requested &= kAllJoints;
  recorded_lost &= kAllJoints;
  plan.to_clear = requested & recorded_lost;
  plan.not_recorded = requested & ~recorded_lost;
  plan.out_of_service = recorded_lost & ~plan.to_clear;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((plan.out_of_service & joint_bit(j)) == 0) continue;
    const JointMask behind = plan.to_clear & joints_lost_by_link_failure_at(j) & ~joint_bit(j);
    if (behind != 0) plan.blocking |= joint_bit(j);
    plan.stranded |= behind;
  }
  return plan;
}

}  // namespace rescue::app
