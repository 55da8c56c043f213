// The robot's 21 joints over EtherCAT: the master (ecat/master/master.hpp) with the robot's network plan,
// its compile-time sized process image, and the joint drive's process data codec
// (drivers/joint/joint_drive_pdo.hpp). This is what the EtherCAT handler task calls every period:
//
//   bus.bring_up(options);                       // once, at start-up (blocking)
//   for (;;) {
//     clock.sleep_until(bus.next_wakeup());      // in step with the DC reference
//     CycleResult r = bus.cycle(references, feedback);
//     while (bus.pop_report(report)) ...         // lost / restored joints -> joint manager
//   }
//
// Joints out of the exchange (lost, not operational, or known lost at start) get all-zero
// outputs whatever the references say, and their feedback is not valid.
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
// 0x607D:01/02 software position limits (not for continuous joints), 0x607F max profile
// velocity, 0x6072 max torque (per mille of the rated torque). Returns how many it wrote.
std::size_t joint_limit_sdos(std::size_t joint, const JointLimits& limits, ecat::SdoRequest* out, std::size_t capacity) noexcept;
constexpr std::size_t kLimitSdosPerJoint = 4;

class JointBus {
 public:
  explicit JointBus(hal::Nic& nic) noexcept : master_(nic, kRobotNetworkPlan, kRobotImageLayout, ByteSpan(image_)) {}

  // Brings the network up; adds every joint's limits (core/robot/robot.hpp) as start-up SDOs.
  Status bring_up(ecat::MasterOptions options) noexcept;

  // One cycle: references of joints in the exchange go out, feedback of valid joints comes back.
  ecat::CycleResult cycle(const JointReferences& references, JointFeedback& feedback) noexcept;

  hal::Nanoseconds next_wakeup() const noexcept { return master_.next_wakeup(); }
  [[nodiscard]] bool pop_report(ecat::LinkReport& out) noexcept { return master_.pop_report(out); }

  // Aperiodic: new limits for a joint's drive, through the mailbox (completions in
  // master().mailbox()). False when the mailbox queue has no room for them all.
  [[nodiscard]] bool request_limits(std::size_t joint, const JointLimits& limits, std::uint32_t tag) noexcept;

  // Explicit re-integration of restored joints (after their `restored` report).
  [[nodiscard]] bool reintegrate(JointMask joints) noexcept {
    return master_.reintegrate(ecat::slaves_of_joints(kRobotNetworkPlan, joints));
  }

  ecat::Master& master() noexcept { return master_; }

 private:
  std::array<std::uint8_t, kRobotImageBytes> image_{};
  ecat::Master master_;
  std::array<ecat::SdoRequest, kJointCount * kLimitSdosPerJoint> startup_sdos_{};
};

}  // namespace rescue::drivers
