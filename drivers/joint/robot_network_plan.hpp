// The robot's EtherCAT network as the master expects it: core/robot/robot.hpp's slaves in frame order,
// each with its device identity (drivers/joint/device_identity.hpp), its process-data sizes and its
// branch. Built at compile time; the process image layout follows from it.
//
// The master (ecat/) speaks in slaves only; which slave carries which joint is known here, in the
// joint driver: kJointOfSlave, joints_of_slaves() and slaves_of_joints().
#pragma once

#include <array>
#include <cstdint>

#include "core/robot/robot.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "ecat/link/network_plan.hpp"

namespace rescue::drivers {

// The robot fits the master's compile-time capacities (ecat/link/master_capacities.hpp).
static_assert(kSlaveCount == ecat::kMaxSlaves, "the master's plan holds exactly the robot's slaves");
static_assert(kBranchCount == ecat::kMaxBranches, "one process-data branch per robot branch");
static_assert(kMasterUpstream == ecat::kMasterUpstream, "the robot's and the master's 'no upstream' agree");

// The joint drive's PDO assignment and mapping as the master sets it up: built from the tables of
// drivers/joint/joint_drive_pdo.hpp, the same ones the drive's object dictionary and SII are built from.
inline constexpr ecat::SlavePdoPlan kJointDrivePdoPlan{
    {0x1C12, kJointRxPdoIndex, kJointRxMappingWords.data(), static_cast<std::uint8_t>(kJointRxMappingWords.size())},
    {0x1C13, kJointTxPdoIndex, kJointTxMappingWords.data(), static_cast<std::uint8_t>(kJointTxMappingWords.size())},
};
static_assert(ecat::mapping_bytes(kJointDrivePdoPlan.outputs) == kJointOutputBytes, "RxPDO plan fills the outputs");
static_assert(ecat::mapping_bytes(kJointDrivePdoPlan.inputs) == kJointInputBytes, "TxPDO plan fills the inputs");

constexpr ecat::NetworkPlan make_robot_network_plan() noexcept {
  ecat::NetworkPlan plan{};
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    const SlaveInfo& s = kSlaves[p];
    const DeviceIdentity& id = identity_of(s.kind);
    const bool joint = s.kind == SlaveKind::joint_drive;
    plan[p] = ecat::SlavePlan{
        s.name,
        id.vendor_id,
        id.product_code,
        id.revision,
        id.name,
        s.station_address,
        station_alias_of(p),
        s.upstream,
        s.upstream_port,
        joint ? static_cast<std::uint8_t>(kJoints[s.joint].branch) : ecat::kNoBranch,
        joint ? static_cast<std::uint16_t>(kJointOutputBytes) : std::uint16_t{0},
        joint ? static_cast<std::uint16_t>(kJointInputBytes) : std::uint16_t{0},
        joint,
        joint,
        joint ? &kJointDrivePdoPlan : nullptr,
    };
  }
  return plan;
}

constexpr ecat::NetworkPlan kRobotNetworkPlan = make_robot_network_plan();
constexpr ecat::ProcessImageLayout kRobotImageLayout = ecat::make_process_image_layout(kRobotNetworkPlan);
constexpr std::size_t kRobotImageBytes = kRobotImageLayout.total_bytes;

// Slave position -> joint (kNoJoint for the junctions).
constexpr std::array<std::uint8_t, ecat::kMaxSlaves> make_joint_of_slave() noexcept {
  std::array<std::uint8_t, ecat::kMaxSlaves> joint{};
  for (std::size_t p = 0; p < kSlaveCount; ++p) joint[p] = kSlaves[p].joint;
  return joint;
}
constexpr std::array<std::uint8_t, ecat::kMaxSlaves> kJointOfSlave = make_joint_of_slave();

// Joints of the slaves in `slaves`.
constexpr JointMask joints_of_slaves(ecat::SlaveMask slaves) noexcept {
  JointMask joints = 0;
  for (std::size_t p = 0; p < ecat::kMaxSlaves; ++p) {
    if ((slaves & ecat::slave_bit(p)) != 0 && kJointOfSlave[p] != kNoJoint) joints |= joint_bit(kJointOfSlave[p]);
  }
  return joints;
}

// Slaves carrying the joints in `joints`.
constexpr ecat::SlaveMask slaves_of_joints(JointMask joints) noexcept {
  ecat::SlaveMask slaves = 0;
  for (std::size_t p = 0; p < ecat::kMaxSlaves; ++p) {
    if (kJointOfSlave[p] != kNoJoint && (joints & joint_bit(kJointOfSlave[p])) != 0) slaves |= ecat::slave_bit(p);
  }
  return slaves;
}

// The name of a slave of the robot (its joint's, or the junction's), "master" for ecat::kMasterEnd,
// "nothing" for any other value: names the two ends of a cable in link diagnostics.
constexpr const char* slave_end_name(std::uint8_t position) noexcept {
  if (position == ecat::kMasterEnd) return "master";
  return position < kSlaveCount ? kSlaves[position].name : "nothing";
}

// The lowest slave of `slaves` (kSlaveCount when empty).
constexpr std::uint8_t first_slave(ecat::SlaveMask slaves) noexcept {
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if ((slaves & ecat::slave_bit(p)) != 0) return static_cast<std::uint8_t>(p);
  }
  return static_cast<std::uint8_t>(kSlaveCount);
}

static_assert(kRobotImageLayout.valid, "a branch has more slaves than ecat::kMaxSlavesPerBranch");
static_assert(kRobotImageBytes == kJointCount * (kJointOutputBytes + kJointInputBytes), "image holds every joint once");

}  // namespace rescue::drivers
