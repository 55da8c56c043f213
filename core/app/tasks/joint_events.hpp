// What the joint manager did, as events: every transition and refusal, every fault with its reason
// and values, each reconfiguration step, every file operation and operator action. The task that owns
// the output (log file, console, operator link) implements JointEventSink; format_event makes the one
// line people read. Events are small fixed records: no heap, no formatting on the joint manager's path.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/robot/joint_fault.hpp"
#include "core/base/result.hpp"
#include "core/robot/robot.hpp"
#include "fsm/machines/joint_status_dfa.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

enum class JointEventKind : std::uint8_t {
  file_absent,           // start-up: no error-joints file, no joint recorded lost
  file_restored,         // start-up: `joints` restored from the file, in Error with their held positions
  file_unusable,         // start-up: the file (or part of it) was not used; `error` says why, `count` records dropped
  file_set_aside,        // the unusable file was renamed for post-mortem (error-joints.bin.unusable[.count])
  file_wiring_added,     // start-up, damaged file: `joints` behind a salvaged lost joint, unreachable too
  file_newer_temporary,  // start-up: a complete newer error-joints.bin.tmp (sequence `count`); `joints` it adds
  file_copy_used,        // start-up: the second copy (sequence `count`) used; `error`: why not the file (ok: older)
  file_unreadable_held,  // start-up: no readable record: `joints` held in Error until cleared by name
  reconfiguration_step,  // `step` 1..5 of the paper's procedure for `joints`
  file_written,          // the error-joints file now holds `joints` (sequence in `count`)
  file_write_failed,     // `error` says why; retried
  transition,            // `joint`: `from` --`input`--> `to`
  refused,               // `joint`: `input` refused in state `from`; `error` says why
  fault,                 // `joint`: `fault` detected (reason, value, limit)
  operator_cleared,      // `joint` cleared by an operator after repair
  operator_clear_refused,// `joint`: the clear was refused; `error` says why
  notice_deferred,       // the handler's notice queue was full; the notice is kept and resent
  auto_cleared,          // `joint` cleared automatically: its drive was power-cycled (configuration's choice)
  lost_joint_returned,   // `joint`, recorded lost, answers again at its held position (awaits the clear)
  lost_joint_moved,      // `joint`, recorded lost, answers again away from its held position: out of
                         // service until the operator confirms (clear with confirmation)
};

const char* to_string(JointEventKind kind) noexcept;

struct JointEvent {
  JointEventKind kind{JointEventKind::transition};
  hal::Nanoseconds time{0};
  std::uint8_t joint{kNoJoint};
  JointMask joints{0};
  fsm::JointState from{fsm::JointState::idle};
  fsm::JointState to{fsm::JointState::idle};
  fsm::JointInput input{fsm::JointInput::fault};
  std::uint8_t step{0};
  std::uint64_t count{0};
  JointFault fault{};
  Error error{};
};

class JointEventSink {
 public:
  JointEventSink() = default;
  JointEventSink(const JointEventSink&) = delete;
  JointEventSink& operator=(const JointEventSink&) = delete;
  JointEventSink(JointEventSink&&) = delete;
  JointEventSink& operator=(JointEventSink&&) = delete;
  virtual ~JointEventSink() = default;
  virtual void on_event(const JointEvent& event) noexcept = 0;
};

// One line, without a newline, e.g. "l_elbow: Enabled --comm_lost--> Error". Returns the length
// written (truncated to fit `capacity`, always NUL-terminated when capacity > 0).
std::size_t format_event(const JointEvent& event, char* out, std::size_t capacity) noexcept;

}  // namespace rescue::app
