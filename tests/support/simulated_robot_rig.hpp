// Test support: the whole simulated robot on virtual time (2 junctions, 21 joint drives, the
// segment with its delays and drifting clocks, the loopback NIC) and the master's JointBus on it.
// Heap allocated by the test (the objects are large); nothing here is firmware.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <string>

#include "core/robot/robot.hpp"
#include "drivers/cia402/cia402_enable.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "drivers/sim/devices/joint_drive_device.hpp"
#include "drivers/sim/devices/junction_device.hpp"
#include "drivers/sim/segment/robot_segment.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "hal/time/clock.hpp"

namespace rescue::testing {

struct SimulatedRobotRig {
  hal::VirtualClock clock{hal::kNsPerSec};
  std::array<std::unique_ptr<drivers::SlaveDevice>, kSlaveCount> devices{};
  std::array<drivers::SegmentSlave, kSlaveCount + 1> slaves{};
  drivers::SimulatedSegment segment;
  drivers::SimulatedNic nic{segment, clock};
  drivers::JointBus bus{nic};

  // The robot as built; with build_now = false the test may first replace devices (wrong device,
  // swapped cables) or add an extra slave, then call build().
  explicit SimulatedRobotRig(bool build_now = true, const drivers::RobotSegmentOptions& options = {}) {
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if (kSlaves[p].kind == SlaveKind::junction) {
        devices[p] = std::make_unique<drivers::JunctionDevice>(p);
      } else {
        devices[p] = std::make_unique<drivers::JointDriveDevice>(p);
      }
    }
    if (build_now) build(options);
  }

  // `extra`: one more slave cabled behind an existing one (its device owned by the test).
  void build(const drivers::RobotSegmentOptions& options = {}, const drivers::SegmentSlave* extra = nullptr) {
    std::array<drivers::SlaveDevice*, kSlaveCount> raw{};
    for (std::size_t p = 0; p < kSlaveCount; ++p) raw[p] = devices[p].get();
    built = drivers::describe_robot_segment(Span<drivers::SlaveDevice* const>(raw.data(), raw.size()), options,
                                            Span<drivers::SegmentSlave>(slaves.data(), kSlaveCount));
    std::size_t count = kSlaveCount;
    if (extra != nullptr) slaves[count++] = *extra;
    if (built.ok()) built = segment.build(Span<const drivers::SegmentSlave>(slaves.data(), count), clock.now());
  }

  drivers::JointDriveDevice& drive(std::size_t joint) {
    return static_cast<drivers::JointDriveDevice&>(*devices[slave_position_of_joint(joint)]);
  }

  // One period: sleep to the master's wake-up, exchange the frame.
  drivers::JointCycleResult cycle(const drivers::JointReferences& references, drivers::JointFeedback& feedback) {
    clock.sleep_until(bus.next_wakeup());
    return bus.cycle(references, feedback);
  }
  // `n` periods with every joint idle (zero references), the master's link reports dropped.
  void idle_cycles(int n) {
    drivers::JointReferences refs{};
    drivers::JointFeedback fb{};
    ecat::LinkReport report;
    for (int i = 0; i < n; ++i) {
      (void)cycle(refs, fb);
      while (bus.master().pop_report(report)) {
      }
    }
  }

  Status built{};
};

// One device more, cabled behind l_hand (the last slave, port 1): an unexpected device plugged in.
// Pass it to SimulatedRobotRig::build; `device` stays the test's.
inline drivers::SegmentSlave extra_slave_behind_the_last(drivers::SlaveDevice& device, const char* name) {
  drivers::SegmentSlave extra;
  extra.name = name;
  extra.upstream = kSlaveCount - 1;
  extra.upstream_port = 1;
  extra.esc = drivers::joint_esc_config();
  extra.link_delay_ns = drivers::kPhyPairDelayNs + 5;
  extra.device = &device;
  return extra;
}

// The bring-up report in words: failed step, error, AL failure, every network difference.
inline std::string describe_master_failure(const ecat::Master& m) {
  char line[ecat::kDifferenceLineCapacity];
  std::string s = m.report().failed_step != nullptr ? m.report().failed_step : "-";
  s += ": ";
  s += m.report().error.what;
  s += " (" + std::to_string(m.report().error.detail0) + ", " + std::to_string(m.report().error.detail1) + ")";
  if (m.report().al_failure.position != 0xFF) {
    (void)ecat::describe(m.report().al_failure, m.plan(), line, sizeof line);
    s += "; ";
    s += line;
  }
  for (const ecat::NetworkDifference& d : m.report().match.differences) {
    (void)ecat::describe(d, m.plan(), m.report().found.span(), line, sizeof line);
    s += "\n  ";
    s += line;
  }
  return s;
}

inline ecat::MasterOptions fast_options() {
  ecat::MasterOptions options;
  // 2000 frames, every one sent (no early end): the figures of the tests that use it stay as recorded.
  options.drift_compensation_frames = 2000;
  options.drift_compensation_target_ns = 0;
  return options;
}

// One step of every drive towards Operation enabled in cyclic position mode, holding where it is.
inline void enable_every_drive_step(drivers::JointReferences& refs, const drivers::JointFeedback& fb) {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    refs[j].mode_of_operation = static_cast<std::int8_t>(ControlMode::cyclic_position);
    refs[j].target_position = fb.joints[j].position_actual;
    refs[j].controlword = drivers::controlword_towards_enabled(fb.joints[j].statusword, refs[j].controlword);
  }
}

// The robot brought up with `options` and cycled until the master is in OP (checked).
inline std::unique_ptr<SimulatedRobotRig> simulated_robot_in_op(const ecat::MasterOptions& options = fast_options()) {
  auto rig = std::make_unique<SimulatedRobotRig>();
  EXPECT_TRUE(rig->bus.bring_up(options).ok()) << describe_master_failure(rig->bus.master());
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  for (int i = 0; i < 200 && rig->bus.master().state() != ecat::MasterState::op; ++i) (void)rig->cycle(refs, fb);
  EXPECT_EQ(rig->bus.master().state(), ecat::MasterState::op);
  return rig;
}

}  // namespace rescue::testing
