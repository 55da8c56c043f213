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
#include "core/robot/joint_sample.hpp"
#include "core/robot/robot.hpp"

namespace rescue {

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
