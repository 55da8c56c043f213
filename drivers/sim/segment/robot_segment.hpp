// The robot's EtherCAT segment as the simulator builds it (design brief section 2, core/robot/robot.hpp):
// junction_a and junction_b (four-port ET1100-class ESCs without an application, like junction
// modules) and 21 joint drives (two-port ESCs of a class common in drives: 3 FMMUs, 4 SMs, 4 KiB,
// 4-byte SII reads), cabled as kSlaves says.
//
// Every slave gets, deterministically from a seed, its own crystal drift (uniform in +-max ppm),
// power-up instant (local time offset) and small variations of its forwarding delays, so
// propagation delays are measurable, differ per position, and runs repeat exactly.
#pragma once

#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "drivers/sim/esc/esc_config.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"

namespace rescue::drivers {

struct RobotSegmentOptions {
  std::uint64_t seed{1};
  double max_drift_ppm{100.0};
  // SimulatedRobot only: one more slave, a spare uncommissioned junction behind the last slave's
  // port 1, powered off (the fault command `extra-slave` powers it on).
  bool spare_slave{false};
  // The ring configuration (core/robot/robot_ring.hpp): one line through every slave, closed back
  // to the master's ring port. Not with spare_slave (the ring cable takes its port).
  bool ring{false};
};

// Cables (100BASE-TX): propagation 5 ns/m plus the two PHYs' latency.
constexpr hal::Nanoseconds kPhyPairDelayNs = 200;
constexpr double kCableNsPerMetre = 5.0;

EscConfig junction_esc_config() noexcept;
EscConfig joint_esc_config() noexcept;

// Fills `out` (kSlaveCount entries) with the robot's slaves in kSlaves order, with `devices[p]` as
// the device of position p, cabled as the tree or (options.ring) as the ring's line. Fails when the
// spans are too short or a device is missing. Drifts and delays are the same in both.
Status describe_robot_segment(Span<SlaveDevice* const> devices, const RobotSegmentOptions& options,
                              Span<SegmentSlave> out) noexcept;

// The ring configuration's ring-return cable (l_hand's port 1 to the master's ring port).
RingCable robot_ring_cable() noexcept;

}  // namespace rescue::drivers
