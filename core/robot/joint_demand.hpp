// What the joint manager wants of each drive (a shared record: the joint manager writes it after
// every step, the EtherCAT handler reads it every cycle). SI units only: the joint driver converts
// the reference to encoder counts (drivers/joint/joint_units.hpp).
// Trivial (no member initialisers): published through a seqlock as bytes; value-initialise it.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "core/robot/robot.hpp"

namespace rescue {

struct JointDemand {
  bool enable;             // DFA state Enabled: power the drive and follow the reference
  std::int8_t mode;        // CiA 402 mode of operation (ControlMode); 0: leave it as it is
  double position_ref_rad; // reference held while no RC task owns the motion
};
static_assert(std::is_trivial_v<JointDemand>, "published through the seqlock as bytes");

using RobotDemand = std::array<JointDemand, kJointCount>;

}  // namespace rescue
