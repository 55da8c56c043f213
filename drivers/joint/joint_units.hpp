// The joint drives' units and the one place they are converted (design brief section 2): the drive
// speaks encoder counts, counts/s and per mille of its rated torque (CiA 402); everything the tasks
// share is in SI units (core/robot/joint_sample.hpp, joint_demand.hpp). Only the joint driver (this
// folder) and the simulated drives that model the hardware (drivers/sim/) convert between them.
#pragma once

#include <cstdint>

#include "core/robot/robot.hpp"

namespace rescue::drivers {

// Joint-side encoder: 2^20 counts per revolution of the joint (after the worm gear).
constexpr double kCountsPerRad = 1048576.0 / 6.283185307179586;
// CiA 402 torques are in per mille of the joint's rated torque (JointInfo::rated_torque_nm).
constexpr double kPerMille = 1000.0;

// Encoder counts <-> radians (joint side). The round trip rad_to_counts(counts_to_rad(c)) == c for
// every int32 c: a reference aligned with an actual position in radians reaches the drive unchanged.
constexpr double counts_to_rad(std::int32_t counts) noexcept { return static_cast<double>(counts) / kCountsPerRad; }
std::int32_t rad_to_counts(double rad) noexcept;  // nearest count; saturates at the int32 range

// Per mille of the rated torque <-> newton metres.
constexpr double per_mille_to_nm(std::int16_t per_mille, const JointInfo& joint) noexcept {
  return static_cast<double>(per_mille) * joint.rated_torque_nm / kPerMille;
}
std::int16_t nm_to_per_mille(double nm, const JointInfo& joint) noexcept;  // saturates at the int16 range

}  // namespace rescue::drivers
