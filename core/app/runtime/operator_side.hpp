// The operator's side of the run (the supervisor, or the main thread with --threads): the clear of
// repaired joints and "initialize robot" sent as local requests once the handler's values show the
// joints reachable, the rescue RC task given the motion, the scenario's cut announced, and at the end
// the Enabled joints disabled through the message parser.
#pragma once

#include <cstdint>

#include "core/app/runtime/run_log.hpp"
#include "core/robot/robot.hpp"

namespace rescue::app::runner {

// The operator's side (the supervisor, or the main thread): the clear of repaired joints, then
// "initialize robot", once the handler's values show the joints reachable; replies printed.
struct OperatorSide {
  JointMask to_clear;
  JointMask out_of_service;
  bool clear_sent;
  bool initialized;
  bool scenario_announced;
  MotionLog motion;  // the motion's changes, read from the segment
};

void operator_side_pass(OperatorSide& side) noexcept;

// Damaged heartbeats the supervisor's liveness watch saw (LivenessWatch::damaged_beats): the run
// summary's segment_records_refused_supervisor.
std::uint64_t liveness_damaged_beats() noexcept;

// After the handler ended: the drives are off; the joint manager's Enabled DFAs follow (Enabled ->
// Ready) through the parser, the joint handle queue's only producer (its answer within its timeout).
// Which joints are Enabled comes from the manager's published demand.
void disable_enabled_joints() noexcept;

}  // namespace rescue::app::runner
