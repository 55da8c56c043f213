// The simulated robot's EtherCAT segment with its devices: junction_a and junction_b, and the 21
// joint drives (drivers/sim/devices/joint_drive_device.hpp), cabled as core/robot/robot.hpp says, with per-slave
// crystal drifts and delays from a seed (drivers/sim/segment/robot_segment.hpp). What `run --nic sim` and
// `sim --iface` put behind the master. Large (the ESC memories): give it static storage.
//
// With RobotSegmentOptions::ring it is the ring configuration (core/robot/robot_ring.hpp,
// docs/redundancy.md): the same 23 slaves in the same auto-increment order, cabled as one line closed
// back to the master's ring port (`sim --iface A --ring-iface B`). The master's two ports are then a
// SimulatedNicPair over segment() (drivers/sim/segment/simulated_nic.hpp). No spare slave in it.
#pragma once

#include <cstddef>

#include "core/base/result.hpp"
#include "drivers/sim/devices/joint_drive_device.hpp"
#include "drivers/sim/devices/junction_device.hpp"
#include "drivers/sim/devices/robot_devices.hpp"
#include "drivers/sim/segment/robot_segment.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "hal/time/clock.hpp"

namespace rescue::drivers {

class SimulatedRobot {
 public:
  // Builds the devices and the segment, powered up at `now`. status() says whether it worked.
  explicit SimulatedRobot(const RobotSegmentOptions& options = {}, hal::Nanoseconds now = 0) noexcept;
  SimulatedRobot(const SimulatedRobot&) = delete;
  SimulatedRobot& operator=(const SimulatedRobot&) = delete;
  SimulatedRobot(SimulatedRobot&&) = delete;
  SimulatedRobot& operator=(SimulatedRobot&&) = delete;
  ~SimulatedRobot() = default;

  const Status& status() const noexcept { return status_; }
  SimulatedSegment& segment() noexcept { return segment_; }
  const SimulatedSegment& segment() const noexcept { return segment_; }
  // The drive of joint `joint` (index into kJoints).
  JointDriveDevice& drive(std::size_t joint) noexcept { return devices_.drive_of_joint(joint); }
  // The spare slave (RobotSegmentOptions::spare_slave): a junction cabled behind the last slave of
  // the segment (port 1), powered off: the segment is the robot's. Powering it on (`extra-slave`)
  // adds one device at the chain's end.
  static constexpr std::size_t kSparePosition = kSlaveCount;
  static constexpr const char* kSpareName = "spare";
  static constexpr std::uint32_t kSpareSerial = 0x00005EA5;

 private:
  RobotDevices devices_;
  JunctionDevice spare_;
  SimulatedSegment segment_;
  Status status_;
};

}  // namespace rescue::drivers
