// The robot's 21 joints over EtherCAT: the master (ecat/master/master.hpp) with the robot's network plan,
// its compile-time sized process image, and the joint drive's process data codec
// (drivers/joint/joint_drive_pdo.hpp). This is what the EtherCAT handler task calls every period:
//
//   bus.bring_up(options, out_of_service);       // once, at start-up (blocking)
//   for (;;) {
//     clock.sleep_until(bus.next_wakeup());      // in step with the DC reference
//     JointCycleResult r = bus.cycle(references, feedback);
//     while (bus.pop_report(report)) ...         // lost / restored joints -> joint manager
//   }
//
// This is where slaves become joints: the master (ecat/) reports slave masks; the bus turns them
// into joint masks (drivers/joint/robot_network_plan.hpp) for the tasks. Joints out of the exchange
// (lost, not operational, or out of service at start) get all-zero outputs whatever the references
// say, and their feedback is not valid.
#pragma once

#include <array>
#include <cstdint>

#include "core/robot/robot.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/master/master.hpp"

namespace rescue::drivers {

using JointReferences = std::array<JointOutputs, kJointCount>;

struct JointFeedback {
  std::array<JointInputs, kJointCount> joints{};
  JointMask valid{0};  // joints whose inputs this cycle brought
};

// SDO downloads that set a joint's limits in its drive (PRE-OP at start-up, or at run time):
// 0x607D:01/02 software position limits (not for continuous joints; written :01 = INT32_MIN, :02,
// :01 so that the drive, which refuses min > max, accepts them whatever it held), 0x607F max profile
// velocity, 0x6072 max torque (per mille of the rated torque). Returns how many it wrote.
std::size_t joint_limit_sdos(std::size_t joint, const JointLimits& limits, ecat::SdoRequest* out, std::size_t capacity) noexcept;
constexpr std::size_t kLimitSdosPerJoint = 5;

// One cycle, in joints (what the EtherCAT handler sees; the master's ecat::CycleResult stays here).
struct JointCycleResult {
  std::uint64_t cycle{0};
  ecat::MasterState state{ecat::MasterState::idle};
  bool frame_received{false};
  hal::Nanoseconds sent_at{0};
  hal::Nanoseconds received_at{0};
  JointMask valid{0};  // joints whose inputs this frame brought
  JointMask out{0};    // joints out of the exchange (out of service, lost, not operational, restored)
};

// A link report of the master, with the joints of its slaves.
struct JointLinkReport {
  ecat::LinkReport link{};
  JointMask joints{0};
};

class JointBus {
 public:
  // `plan`: the tree's (kRobotNetworkPlan) or the ring configuration's (kRobotRingNetworkPlan, with a
  // ring NIC): the same slaves, positions and process image, other cables.
  explicit JointBus(hal::Nic& nic, const ecat::NetworkPlan& plan = kRobotNetworkPlan) noexcept
      : master_(nic, plan, kRobotImageLayout, ByteSpan(image_)) {}

  // Brings the network up; adds the limits of every joint in service (core/robot/robot.hpp) as
  // start-up SDOs. The joints of `out_of_service` (recorded lost) are held out: when their slaves
  // answer they join the topology and the distributed clocks, never the exchange.
  Status bring_up(ecat::MasterOptions options, JointMask out_of_service = 0) noexcept;

  // One cycle: references of joints in the exchange go out, feedback of valid joints comes back.
  // The master's own result of the last cycle stays available as last_cycle().
  JointCycleResult cycle(const JointReferences& references, JointFeedback& feedback) noexcept;
  const ecat::CycleResult& last_cycle() const noexcept { return last_cycle_; }

  hal::Nanoseconds next_wakeup() const noexcept { return master_.next_wakeup(); }
  [[nodiscard]] bool pop_report(JointLinkReport& out) noexcept;

  // Aperiodic: new limits for a joint's drive, through the mailbox (completions in
  // master().mailbox()). False when the mailbox queue has no room for them all.
  [[nodiscard]] bool request_limits(std::size_t joint, const JointLimits& limits, std::uint32_t tag) noexcept;

  // Explicit re-integration of restored joints (after their `restored` report).
  [[nodiscard]] bool reintegrate(JointMask joints) noexcept {
    return master_.reintegrate(slaves_of_joints(joints));
  }

  ecat::Master& master() noexcept { return master_; }

 private:
  std::array<std::uint8_t, kRobotImageBytes> image_{};
  ecat::Master master_;
  std::array<ecat::SdoRequest, kJointCount * kLimitSdosPerJoint> startup_sdos_{};
  ecat::CycleResult last_cycle_{};
};

}  // namespace rescue::drivers
