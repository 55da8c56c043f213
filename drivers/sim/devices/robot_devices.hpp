// The device applications of the whole robot, in fixed storage: the two junctions and the 21
// joint drives (drivers/sim/devices/junction_device.hpp, drivers/sim/devices/joint_drive_device.hpp), each built for its
// slot of kSlaves. devices() is what describe_robot_segment (drivers/sim/segment/robot_segment.hpp) takes.
#pragma once

#include <array>
#include <cstddef>
#include <utility>

#include "core/robot/robot.hpp"
#include "drivers/sim/devices/joint_drive_device.hpp"
#include "drivers/sim/devices/junction_device.hpp"
#include "drivers/sim/devices/slave_device.hpp"

namespace rescue::drivers {

namespace robot_devices_detail {
// Position in kSlaves of the n-th slave of `kind`.
constexpr std::size_t position_of(SlaveKind kind, std::size_t n) noexcept {
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (kSlaves[p].kind == kind && n-- == 0) return p;
  }
  return kSlaveCount;
}
}  // namespace robot_devices_detail

class RobotDevices {
 public:
  RobotDevices() noexcept : RobotDevices(std::make_index_sequence<kJunctionCount>{}, std::make_index_sequence<kJointCount>{}) {}

  // Device of each slave position, in kSlaves order.
  const std::array<SlaveDevice*, kSlaveCount>& devices() const noexcept { return by_position_; }
  // The drive of joint `joint` (index into kJoints).
  JointDriveDevice& drive_of_joint(std::size_t joint) noexcept;

 private:
  template <std::size_t... J, std::size_t... D>
  RobotDevices(std::index_sequence<J...>, std::index_sequence<D...>) noexcept
      : junctions_{{JunctionDevice(robot_devices_detail::position_of(SlaveKind::junction, J))...}},
        drives_{{JointDriveDevice(robot_devices_detail::position_of(SlaveKind::joint_drive, D))...}} {
    for (JunctionDevice& j : junctions_) by_position_[index_of(j)] = &j;
    for (std::size_t d = 0; d < drives_.size(); ++d) {
      by_position_[robot_devices_detail::position_of(SlaveKind::joint_drive, d)] = &drives_[d];
    }
  }
  std::size_t index_of(const JunctionDevice& j) const noexcept {
    return robot_devices_detail::position_of(SlaveKind::junction, static_cast<std::size_t>(&j - junctions_.data()));
  }

  std::array<JunctionDevice, kJunctionCount> junctions_;
  std::array<JointDriveDevice, kJointCount> drives_;
  std::array<SlaveDevice*, kSlaveCount> by_position_{};
};

}  // namespace rescue::drivers
