#include "drivers/robot_devices.hpp"

#include <cassert>

namespace rescue::drivers {

JointDriveDevice& RobotDevices::drive_of_joint(std::size_t joint) noexcept {
  // kSlaves lists the drives in frame order; their joint indices differ from that order.
  for (JointDriveDevice& d : drives_) {
    if (d.joint() == joint) return d;
  }
  assert(false && "every joint has a drive (core/robot.hpp robot_checks)");
  return drives_[0];
}

}  // namespace rescue::drivers
