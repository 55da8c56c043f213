// Test support: the whole simulated robot on virtual time (2 junctions, 21 joint drives, the
// segment with its delays and drifting clocks, the loopback NIC) and the master's JointBus on it.
// Heap allocated by the test (the objects are large); nothing here is firmware.
#pragma once

#include <array>
#include <memory>

#include "core/robot.hpp"
#include "drivers/joint_bus.hpp"
#include "drivers/joint_drive_device.hpp"
#include "drivers/junction_device.hpp"
#include "drivers/robot_segment.hpp"
#include "drivers/simulated_nic.hpp"
#include "drivers/simulated_segment.hpp"
#include "hal/clock.hpp"

namespace rescue::testing {

struct SimulatedRobotRig {
  hal::VirtualClock clock{hal::kNsPerSec};
  std::array<std::unique_ptr<drivers::SlaveDevice>, kSlaveCount> devices{};
  std::array<drivers::SegmentSlave, kSlaveCount> slaves{};
  drivers::SimulatedSegment segment;
  drivers::SimulatedNic nic{segment, clock};
  drivers::JointBus bus{nic};

  // Builds the robot; `skip` leaves slots empty (the rig then describes fewer slaves).
  explicit SimulatedRobotRig(const drivers::RobotSegmentOptions& options = {}) {
    std::array<drivers::SlaveDevice*, kSlaveCount> raw{};
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if (kSlaves[p].kind == SlaveKind::junction) {
        devices[p] = std::make_unique<drivers::JunctionDevice>(p);
      } else {
        devices[p] = std::make_unique<drivers::JointDriveDevice>(p);
      }
      raw[p] = devices[p].get();
    }
    built = drivers::describe_robot_segment(Span<drivers::SlaveDevice* const>(raw.data(), raw.size()), options,
                                            Span<drivers::SegmentSlave>(slaves.data(), slaves.size()));
    if (built.ok()) built = segment.build(Span<const drivers::SegmentSlave>(slaves.data(), slaves.size()), clock.now());
  }

  drivers::JointDriveDevice& drive(std::size_t joint) {
    return static_cast<drivers::JointDriveDevice&>(*devices[slave_position_of_joint(joint)]);
  }

  // One period: sleep to the master's wake-up, exchange the frame.
  ecat::CycleResult cycle(const drivers::JointReferences& references, drivers::JointFeedback& feedback) {
    clock.sleep_until(bus.next_wakeup());
    return bus.cycle(references, feedback);
  }

  Status built{};
};

inline ecat::MasterOptions fast_options() {
  ecat::MasterOptions options;
  options.drift_compensation_frames = 2000;  // enough on the model; the bench runs the full 15000
  return options;
}

}  // namespace rescue::testing
