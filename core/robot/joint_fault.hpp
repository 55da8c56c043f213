// Why a joint is in Error: the reason the joint manager records (and the error-joints file stores),
// with the offending value and the limit it crossed, so operators see "l_elbow: velocity 2.31 rad/s
// above 2.00 rad/s", not just "Error".
#pragma once

#include <cstdint>

namespace rescue {

// Stored as one byte in the error-joints file: values are fixed forever (append only).
enum class FaultReason : std::uint8_t {
  none = 0,
  comm_lost = 1,                 // the EtherCAT handler cannot reach the joint
  drive_fault = 2,               // the drive reports a fault (value = its error code)
  position_reference_limit = 3,  // commanded position outside [min, max]
  velocity_reference_limit = 4,  // commanded |velocity| above the maximum
  torque_reference_limit = 5,    // commanded |torque| above the maximum
  position_limit = 6,            // actual position outside [min, max]
  velocity_limit = 7,            // actual |velocity| above the maximum
  torque_limit = 8,              // actual |torque| above the maximum
  not_finite = 9,                // a NaN or infinite value where a number was expected
  record_unreadable = 10,        // no readable record of the lost joints: held until cleared by name
  acceleration_reference_limit = 11,  // a reference sent changed speed faster than the acceleration limit
  jerk_reference_limit = 12,     // a reference sent changed acceleration faster than the jerk limit
};

constexpr std::uint8_t kFaultReasonMax = 12;

constexpr bool is_valid_fault_reason(std::uint8_t raw) noexcept { return raw <= kFaultReasonMax; }

const char* to_string(FaultReason reason) noexcept;

struct JointFault {
  FaultReason reason{FaultReason::none};
  double value{0.0};  // the offending value (SI units; the error code for drive_fault)
  double limit{0.0};  // the limit it crossed (SI units; 0 when there is none)
  bool active() const noexcept { return reason != FaultReason::none; }
};

}  // namespace rescue
