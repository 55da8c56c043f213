// The operator's clear of repaired joints at start-up (`run --clear-joint NAMES`), judged against the
// joints the error-joints file restored, before the network comes up.
//
// A joint answers only through the joints before it on its branch, so a joint behind one that stays
// recorded lost cannot be expected back: such a request is refused whole (nothing is cleared).
#pragma once

#include "core/robot/robot.hpp"

namespace rescue::app {

struct RepairedJointsPlan {
  JointMask to_clear{0};        // requested and recorded lost: expected on the network, cleared once in OP
  JointMask not_recorded{0};    // requested but not recorded lost: nothing to clear
  JointMask stranded{0};        // requested, but behind a joint that stays lost (refuses the request)
  JointMask blocking{0};        // the joints that stay lost with a requested joint behind them
  JointMask out_of_service{0};  // recorded lost and not cleared: the master expects them absent

  bool refused() const noexcept { return stranded != 0; }
};

RepairedJointsPlan plan_repaired_joints(JointMask requested, JointMask recorded_lost) noexcept;

}  // namespace rescue::app
