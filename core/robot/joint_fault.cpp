#include "core/robot/joint_fault.hpp"

namespace rescue {

const char* to_string(FaultReason reason) noexcept {
  switch (reason) {
    case FaultReason::none: return "none";
    case FaultReason::comm_lost: return "communication lost";
    case FaultReason::drive_fault: return "drive fault";
    case FaultReason::position_reference_limit: return "position reference out of limits";
    case FaultReason::velocity_reference_limit: return "velocity reference above limit";
    case FaultReason::torque_reference_limit: return "torque reference above limit";
    case FaultReason::position_limit: return "position out of limits";
    case FaultReason::velocity_limit: return "velocity above limit";
    case FaultReason::torque_limit: return "torque above limit";
    case FaultReason::not_finite: return "value not finite";
    case FaultReason::record_unreadable: return "no readable record of lost joints";
    case FaultReason::acceleration_reference_limit: return "reference acceleration";
    case FaultReason::jerk_reference_limit: return "reference jerk";
  }
  return "unknown";
}

}  // namespace rescue
