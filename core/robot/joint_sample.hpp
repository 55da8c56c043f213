// What the EtherCAT handler publishes of each joint every cycle (a shared record: every task reads
// it). SI units only: the joint driver (drivers/joint/joint_units.hpp) converts the drive's counts
// and per-mille torques. When a joint becomes unreachable the handler clears `reachable` and leaves
// the last values it received in place: they are the joint's last known state (reconfiguration
// step 2 reads them).
// A trivial type (no member initialisers) so it can be published through the seqlock as bytes;
// value-initialise it (`JointSample s{};`): all zero, unreachable.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "core/robot/robot.hpp"

namespace rescue {

struct JointSample {
  bool reachable;                  // this cycle's working counter included the joint, or the handler carries it
                                   // (driven, still in the exchange, this frame late or lost: last values)
  double position_rad;             // actual, as the drive reported it
  double velocity_rad_s;
  double torque_nm;
  double position_ref_rad;         // what the handler sends this cycle
  double velocity_ref_rad_s;       // the speed of the position references sent (CSP: no velocity target is sent)
  double torque_ref_nm;
  bool drive_fault;                // statusword fault bit
  std::uint16_t drive_error_code;  // CiA 402 error code (0x603F)
};
static_assert(std::is_trivial_v<JointSample>, "published through the seqlock as bytes");

using RobotSample = std::array<JointSample, kJointCount>;

}  // namespace rescue
