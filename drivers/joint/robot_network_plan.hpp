// The robot's EtherCAT network as the master expects it: core/robot/robot.hpp's slaves in frame order,
// each with its device identity (drivers/joint/device_identity.hpp), its process-data sizes and its
// branch. Built at compile time; the process image layout follows from it.
#pragma once

#include <cstdint>

#include "core/robot/robot.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "ecat/master/network_plan.hpp"

namespace rescue::drivers {


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
        s.joint,
        joint ? static_cast<std::uint16_t>(kJointOutputBytes) : std::uint16_t{0},
        joint ? static_cast<std::uint16_t>(kJointInputBytes) : std::uint16_t{0},
        joint,
        joint,
    };
  }
  return plan;
}

constexpr ecat::NetworkPlan kRobotNetworkPlan = make_robot_network_plan();
constexpr ecat::ProcessImageLayout kRobotImageLayout = ecat::make_process_image_layout(kRobotNetworkPlan);
constexpr std::size_t kRobotImageBytes = kRobotImageLayout.total_bytes;

static_assert(kRobotImageLayout.valid, "a branch has more slaves than ecat::kMaxSlavesPerBranch");
static_assert(kRobotImageBytes == kJointCount * (kJointOutputBytes + kJointInputBytes), "image holds every joint once");

}  // namespace rescue::drivers
