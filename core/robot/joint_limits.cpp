#include "core/robot/joint_limits.hpp"

#include <cmath>

namespace rescue {
namespace {

JointFault fault(FaultReason reason, double value, double limit) noexcept { return JointFault{reason, value, limit}; }

// Position in [min, max], |velocity| <= vmax, |torque| <= tmax; NaN/inf is its own reason so a broken
// conversion never passes as "within limits" (every comparison with NaN is false).
JointFault check(double position, double velocity, double torque, const JointInfo& joint, FaultReason position_reason,
                 FaultReason velocity_reason, FaultReason torque_reason) noexcept {
  if (!std::isfinite(position)) return fault(FaultReason::not_finite, 0.0, 0.0);
  if (!std::isfinite(velocity)) return fault(FaultReason::not_finite, 1.0, 0.0);
  if (!std::isfinite(torque)) return fault(FaultReason::not_finite, 2.0, 0.0);
  const JointLimits& lim = joint.limits;
  if (!joint.continuous) {
    if (position < lim.position_min_rad) return fault(position_reason, position, lim.position_min_rad);
    if (position > lim.position_max_rad) return fault(position_reason, position, lim.position_max_rad);
  }
  if (std::fabs(velocity) > lim.velocity_max_rad_s) return fault(velocity_reason, velocity, lim.velocity_max_rad_s);
  if (std::fabs(torque) > lim.torque_max_nm) return fault(torque_reason, torque, lim.torque_max_nm);
  return JointFault{};
}

}  // namespace

JointFault check_actual_limits(const JointSample& s, const JointInfo& joint) noexcept {
  return check(s.position_rad, s.velocity_rad_s, s.torque_nm, joint, FaultReason::position_limit,
               FaultReason::velocity_limit, FaultReason::torque_limit);
}

JointFault check_reference_limits(const JointSample& s, const JointInfo& joint) noexcept {
  return check(s.position_ref_rad, s.velocity_ref_rad_s, s.torque_ref_nm, joint, FaultReason::position_reference_limit,
               FaultReason::velocity_reference_limit, FaultReason::torque_reference_limit);
}

JointFault check_drive_fault(const JointSample& s) noexcept {
  if (!s.drive_fault) return JointFault{};
  return fault(FaultReason::drive_fault, static_cast<double>(s.drive_error_code), 0.0);
}

SafeStopDecision decide_safe_stop(const RobotSample& sample, JointMask monitored) noexcept {
  SafeStopDecision decision;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((monitored & joint_bit(j)) == 0) continue;
    JointFault f = check_actual_limits(sample[j], kJoints[j]);
    if (!f.active()) f = check_reference_limits(sample[j], kJoints[j]);
    if (!f.active()) continue;
    decision.violating |= joint_bit(j);
    if (!decision.stop) {
      decision.stop = true;
      decision.first_joint = static_cast<std::uint8_t>(j);
      decision.first = f;
    }
  }
  return decision;
}

}  // namespace rescue
