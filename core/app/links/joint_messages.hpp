// Messages between the EtherCAT handler, the message parser and the joint manager (design brief
// sections 3 and 6). Plain fixed-size records, copied through bounded queues (core/concurrency/message_port.hpp).
#pragma once

#include <cstdint>

#include "core/base/result.hpp"
#include "core/robot/robot.hpp"
#include "fsm/machines/joint_status_dfa.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

// Reconfiguration step 1, handler -> joint manager: joints the handler can no longer reach.
struct LostJointsReport {
  JointMask lost{0};               // every joint found unreachable (may repeat joints already reported)
  std::uint64_t cycle{0};          // the handler cycle that confirmed the loss
  hal::Nanoseconds detected_at{0}; // monotonic time of that cycle
};

enum class NoticeKind : std::uint8_t {
  lost_joints_recorded,  // step 4: the answer to a LostJointsReport
  joints_cleared,        // an operator cleared repaired joints: the handler may command them again
};

// Joint manager -> handler.
struct JointManagerNotice {
  NoticeKind kind{NoticeKind::lost_joints_recorded};
  JointMask joints{0};
  std::uint64_t cycle{0};          // the report's cycle (lost_joints_recorded)
  Errc file_status{Errc::ok};      // ok: the error-joints file holds the change durably
};

enum class JointCommandKind : std::uint8_t {
  dfa_input,    // `input` for each joint of `joints`
  clear_lost,   // operator: `joints` were repaired; unlatch their loss and drop them from the error file
};

// Message parser -> joint manager (the paper's "joint handle queue"): one DFA input for a set of
// joints, or the operator's clear of repaired joints (logged, refused while a joint is unreachable).
struct JointCommand {
  JointMask joints{0};
  fsm::JointInput input{fsm::JointInput::disable};
  ControlMode mode{ControlMode::none};  // the mode for select_mode
  JointCommandKind kind{JointCommandKind::dfa_input};
};

}  // namespace rescue::app
