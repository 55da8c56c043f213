// Limit monitoring (design brief section 3): pure functions over one cycle's joint values, used by
// two independent checkers:
//   - the joint manager, which sends `fault` to one joint's DFA with the reason recorded;
//   - the EtherCAT handler, whose own check (decide_safe_stop) stops the whole robot safely
//     (every drive disabled, worm gears holding) whatever the joint manager does.
// No heap, no state, bounded time: a fixed loop over the 21 joints.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "core/robot/joint_fault.hpp"
#include "core/robot/robot.hpp"

namespace rescue {

// One joint's values in one cycle, in SI units (the handler converts the process data: counts with
// counts_to_rad, per-mille torque with the joint's rated torque). Written by the EtherCAT handler into
// shared memory; read by the joint manager. When a joint becomes unreachable the handler clears
// `reachable` and leaves the last values it received in place: they are the joint's last known state
// (reconfiguration step 2 reads them).
// A trivial type (no member initialisers) so it can be published through the seqlock as bytes;
// value-initialise it (`JointSample s{};`): all zero, unreachable.
struct JointSample {
  bool reachable;                  // this cycle's working counter included the joint
  std::int32_t position_counts;    // actual position as the drive reported it (held position record)
  double position_rad;             // actual
  double velocity_rad_s;
  double torque_nm;
  double position_ref_rad;         // what the handler sends this cycle
  double velocity_ref_rad_s;
  double torque_ref_nm;
  bool drive_fault;                // statusword fault bit
  std::uint16_t drive_error_code;  // CiA 402 error code (0x603F)
};
static_assert(std::is_trivial_v<JointSample>, "published through the seqlock as bytes");

using RobotSample = std::array<JointSample, kJointCount>;

// Actual values: position within [min, max] (not for continuous joints), |velocity| and |torque| within
// their maxima, all finite. The first violation found, or reason none.
JointFault check_actual_limits(const JointSample& sample, const JointInfo& joint) noexcept;

// Commanded values, the same limits.
JointFault check_reference_limits(const JointSample& sample, const JointInfo& joint) noexcept;

// The drive's own fault report as a JointFault (value = error code).
JointFault check_drive_fault(const JointSample& sample) noexcept;

struct SafeStopDecision {
  bool stop{false};                  // true: disable every drive now and hold
  JointMask violating{0};            // every monitored joint over a limit this cycle
  std::uint8_t first_joint{kNoJoint};
  JointFault first{};                // the first violation, for the log line
};

// The EtherCAT handler's check, called every cycle: actual and commanded values of every joint in
// `monitored` (reachable joints the handler commands; lost joints are excluded) against the robot's
// limits. stop = any violation.
SafeStopDecision decide_safe_stop(const RobotSample& sample, JointMask monitored) noexcept;

}  // namespace rescue
