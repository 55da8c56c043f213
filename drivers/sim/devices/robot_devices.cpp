#include "drivers/sim/devices/robot_devices.hpp"

#include <algorithm>
#include <cassert>

namespace rescue::drivers {

JointDriveDevice& RobotDevices::drive_of_joint(std::size_t joint) noexcept {
  // kSlaves lists the drives in frame order; their joint indices differ from that order.
  auto* it = std::find_if(drives_.begin(), drives_.end(), [joint](const JointDriveDevice& d) { return d.joint() == joint; });
  assert(it != drives_.end() && "every joint has a drive (core/robot/robot.hpp robot_checks)");
  return it != drives_.end() ? *it : drives_[0];
}

}  // namespace rescue::drivers
