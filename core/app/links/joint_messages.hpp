// Messages between the EtherCAT handler, the message parser and the joint manager (design brief
// sections 3 and 6). Plain fixed-size records, copied through bounded queues (core/concurrency/message_port.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "core/app/links/protocol_messages.hpp"
#include "core/base/result.hpp"
#include "core/robot/joint_fault.hpp"
#include "core/robot/robot.hpp"
#include "fsm/machines/joint_status_dfa.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

// Reconfiguration step 1, handler -> joint manager: joints the handler can no longer reach.
struct LostJointsReport {
  JointMask lost{0};               // every joint found unreachable (may repeat joints already reported)
  std::uint64_t cycle{0};          // the handler cycle that confirmed the loss
  hal::Nanoseconds detected_at{0}; // monotonic time of that cycle
  // Joints whose drive the master brought back after a power cycle (it had lost its station
  // address), with `lost` 0: the joint manager may clear them automatically (auto_clear_power_cycled).
  JointMask back_after_power_cycle{0};
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
  // The same, and the operator confirms that a joint whose position differs from the held position
  // recorded in the file may return to service (clear_lost refuses it).
  clear_lost_moved,
};

// Message parser -> joint manager (the paper's "joint handle queue"): one DFA input for a set of
// joints, or the operator's clear of repaired joints (logged, refused while a joint is unreachable).
struct JointCommand {
  JointMask joints{0};
  fsm::JointInput input{fsm::JointInput::disable};
  ControlMode mode{ControlMode::none};  // the mode for select_mode
  JointCommandKind kind{JointCommandKind::dfa_input};
  std::uint32_t request{0};             // the parser's request id; 0: nobody waits for the outcome
  // All or nothing (operator requests): the request's `steps` commands (this one is number `step`)
  // are checked together against every joint first; if any joint must refuse, none is applied.
  bool all_or_nothing{false};
  std::uint8_t step{0};
  std::uint8_t steps{1};
};
constexpr std::size_t kMaxRequestSteps = 5;  // the longest request: initialize (3 select_mode, set_reference, enable)

// Why the joint manager did not apply a command to a joint.
enum class CommandRefusal : std::uint8_t {
  none,
  state_machine,  // the DFA has no transition for this input in the joint's state (or its guard said no)
  unreachable,    // the joint does not answer (only disable and reset are taken)
  bad_mode,       // select_mode without CSP, CSV or CST
  clear_refused,  // clear_lost refused (still unreachable, not recorded lost, or file not written)
};

// Joint manager -> message parser: one joint's refusal, as the operator's reply names it.
struct JointRefusalNote {
  protocol::JointRefusal why{protocol::JointRefusal::none};
  fsm::JointState state{fsm::JointState::idle};
  fsm::JointInput input{fsm::JointInput::disable};
};

// Joint manager -> message parser: what became of a command that carried a request id.
struct JointCommandOutcome {
  std::uint32_t request{0};
  JointMask applied{0};
  JointMask refused{0};
  CommandRefusal first_reason{CommandRefusal::none};  // of the lowest refused joint
  std::uint8_t first_joint{0};
  fsm::JointState first_state{fsm::JointState::idle};
  fsm::JointInput input{fsm::JointInput::disable};
  JointCommandKind kind{JointCommandKind::dfa_input};
  std::array<JointRefusalNote, kJointCount> notes{};  // every refused joint's own reason
};

// What the joint manager publishes about one joint (shared memory, read by the handler, the RC
// tasks, and the socket handler for the operator's status).
struct JointStatus {
  fsm::JointState state{fsm::JointState::idle};
  ControlMode mode{ControlMode::none};
  bool drive_enabled{false};
  bool lost{false};                         // recorded lost: RC tasks plan without it
  double reference_position_rad{0.0};
  double held_position_rad{0.0};            // where a lost joint's worm gear holds it
  JointFault fault{};                       // why it is (or was last) in Error
};

// JointStatus as published through the seqlock (trivial: copied as bytes between tasks/processes).
struct PublishedJointStatus {
  fsm::JointState state;
  ControlMode mode;
  bool drive_enabled;
  bool lost;
  FaultReason fault;  // why it is (or was last) in Error
  double reference_position_rad;
  double held_position_rad;
  double fault_value;
  double fault_limit;
};
static_assert(std::is_trivial_v<PublishedJointStatus>, "published through the seqlock as bytes");
using RobotJointStatus = std::array<PublishedJointStatus, kJointCount>;

inline RobotJointStatus published_status(const std::array<JointStatus, kJointCount>& statuses) noexcept {
  RobotJointStatus out{};
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointStatus& s = statuses[j];
    out[j] = PublishedJointStatus{s.state, s.mode, s.drive_enabled, s.lost, s.fault.reason,
                                  s.reference_position_rad, s.held_position_rad, s.fault.value, s.fault.limit};
  }
  return out;
}

}  // namespace rescue::app
