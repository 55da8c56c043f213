// The joint manager task (design brief sections 3, 5, 6; paper III-B and IV-C): one joint status DFA
// per joint, limit monitoring, and the reconfiguration procedure after damage.
//
// It runs as a high-priority periodic task (CPU thread 2). Everything it talks to is an interface
// (JointManagerPorts), so the same code runs in the firmware (shared-memory queues and snapshots),
// on threads of one process, and in tests on virtual time. It holds no locks and never waits. The
// one slow operation, the durable file write, happens here, on the joint manager's own thread. The
// EtherCAT handler only queues a report and reads the answer later (core/app/tasks/lost_joint_tracker.hpp),
// so the file write never blocks it.
//
// Per period, step(now):
//   1. read the handler's latest joint values (one consistent snapshot);
//   2. reconfigure for each lost-joints report (paper steps 1-5: report, read last state, write the
//      file, answer, mark comm_lost);
//   3. resend deferred notices, and retry a failed file write;
//   4. apply queued joint commands (the message parser's joint handle queue) to the DFAs;
//   5. limit monitoring: drive fault, actual position/velocity/torque, and for Enabled joints the
//      commanded values -> `fault` with the reason recorded;
//   6. publish each joint's status (statuses()) for the shared memory.
// Bounded: at most kMaxReportsPerStep reports and kMaxCommandsPerStep commands per step. No heap.
#pragma once

#include <array>
#include <cstdint>

#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/joint_events.hpp"
#include "core/app/links/joint_messages.hpp"
#include "core/app/links/joint_sample_source.hpp"
#include "core/robot/error_joints_file.hpp"
#include "core/containers/fixed_vector.hpp"
#include "core/robot/joint_limits.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/app/links/joint_demand_sink.hpp"
#include "fsm/machines/joint_status_dfa.hpp"
#include "hal/time/clock.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {

struct JointManagerPorts {
  MessageSource<LostJointsReport>* reports;    // from the EtherCAT handler (step 1)
  MessageSink<JointManagerNotice>* notices;    // to the EtherCAT handler (step 4, operator clears)
  MessageSource<JointCommand>* commands;       // the joint handle queue, from the message parser
  JointSampleSource* samples;                  // the handler's published joint values (step 2, monitoring)
  ErrorJointsStorage* storage;                 // the error-joints file (step 3, start-up)
  hal::WallClock* wall_clock;                  // Unix time for the file's records
  JointEventSink* events;                      // what happened, for the log
  JointDemandSink* demand{nullptr};            // its drive demand, after every step (nullptr: not published)
  MessageSink<JointCommandOutcome>* outcomes{nullptr};  // to the message parser (commands with a request id)
};

// JointStatus, what it publishes per joint, is in core/app/links/joint_messages.hpp.

struct RestoreReport {
  JointMask restored{0};        // joints put in Error from the file (all of the masks below)
  bool file_present{false};
  Status file_status;           // success, or why the file (or part of it) was not used
  std::uint32_t records_dropped{0};
  JointMask salvaged{0};        // damaged file: the joints of the records that passed their checks
  JointMask added_behind{0};    // damaged file: joints behind a salvaged one on its branch (unreachable too)
  JointMask from_temporary{0};  // joints only a complete newer error-joints.bin.tmp lists
  bool newer_temporary{false};  // such a temporary file was found (an interrupted write)
  std::uint64_t temporary_sequence{0};
  bool set_aside{false};        // the unusable file was kept aside (set_aside_name(set_aside_suffix))
  std::uint32_t set_aside_suffix{0};
  bool damaged() const noexcept { return file_present && !file_status.ok(); }
};

class JointManager {
 public:
  static constexpr std::size_t kMaxReportsPerStep = 4;
  static constexpr std::size_t kMaxCommandsPerStep = 32;
  static constexpr std::size_t kMaxDeferredNotices = 8;
  static constexpr hal::Nanoseconds kWriteRetryPeriod = 100 * hal::kNsPerMs;

  // Every port must be non-null.
  explicit JointManager(const JointManagerPorts& ports) noexcept;

  // Start-up, before the network comes up: reads the error-joints file; its joints start in Error
  // (loss latched, held position known). An unusable file is reported, kept aside under a name of its
  // own, and whatever part of it can be trusted is restored and rewritten; the salvage follows the
  // wiring (a joint behind a salvaged lost joint on its branch was unreachable too, so it is recorded
  // lost as well). A complete newer temporary file (a write interrupted before its rename) is
  // reported and its joints kept lost. The robot starts safely either way.
  RestoreReport restore(hal::Nanoseconds now) noexcept;

  // One period (see the file comment).
  void step(hal::Nanoseconds now) noexcept;

  // Operator action after a repair, logged: the joint must be reachable again. It is removed from the
  // error-joints file (durably, or the clear is refused), its loss is unlatched and the handler told;
  // the joint stays in Error until a `reset` command.
  Status clear_lost_joint(std::size_t joint, hal::Nanoseconds now) noexcept;
  // The same for a set of joints (the operator's `clear_lost` command): each joint is judged alone and
  // logged; those that may be cleared leave the file in one write. The first refusal is returned.
  // A joint that answers again away from the held position recorded in the file (more than
  // kHeldPositionToleranceRad) is refused unless `confirmed_moved` holds it.
  Status clear_lost_joints(JointMask joints, hal::Nanoseconds now, JointMask confirmed_moved = 0,
                           bool automatic = false) noexcept;
  // The configuration's choice: a joint whose drive was power-cycled (and brought back by the
  // master) is cleared and reset to Idle without the operator, unless it moved from its held position.
  void set_auto_clear_power_cycled(bool on) noexcept { auto_clear_power_cycled_ = on; }
  static constexpr double kHeldPositionToleranceRad = 0.01;
  // The current position minus the held one recorded in the file (0 when none is recorded).
  double offset_from_held(std::size_t joint) const noexcept;

  const std::array<JointStatus, kJointCount>& statuses() const noexcept { return status_; }
  std::array<fsm::JointState, kJointCount> states() const noexcept;
  fsm::RobotStatusSummary summary() const noexcept { return fsm::summarize(states()); }
  JointMask lost_joints() const noexcept { return lost_; }
  // Every joint latched lost since start (restored from the file included), cleared or not.
  JointMask lost_since_start() const noexcept { return lost_since_start_; }
  const ErrorJointsContents& recorded() const noexcept { return recorded_; }

  std::uint32_t refused_commands() const noexcept { return refused_commands_; }
  std::uint32_t file_writes() const noexcept { return file_writes_; }
  std::uint32_t file_write_failures() const noexcept { return file_write_failures_; }
  bool file_dirty() const noexcept { return file_dirty_; }
  std::uint32_t outcomes_dropped() const noexcept { return outcomes_dropped_; }

 private:
  struct Joint {
    fsm::JointStatusMachine machine;
    fsm::JointContext context;
    JointFault fault;
    double held_position_rad{0.0};
  };

  void handle_report(const LostJointsReport& report, hal::Nanoseconds now) noexcept;
  void receive_command(const JointCommand& command, hal::Nanoseconds now) noexcept;
  void apply_command(const JointCommand& command, hal::Nanoseconds now) noexcept;
  // All or nothing: the whole request in batch_ is tried on copies of the joints first; applied only
  // when no joint refuses, else every blocking joint is reported with its reason and nothing changes.
  void apply_request(hal::Nanoseconds now) noexcept;
  // Why joint j may not be cleared now (none: it may), given the lost joints `lost`.
  protocol::JointRefusal clear_refusal(std::size_t j, JointMask lost, bool confirmed_moved) const noexcept;
  // Why joint `joint` (its machine and context as given) refuses `command` now (none: it accepts).
  protocol::JointRefusal dfa_refusal(std::size_t j, const JointCommand& command, JointMask lost,
                                     const fsm::JointStatusMachine& machine, fsm::JointContext& context) const noexcept;
  void report_outcome(const JointCommandOutcome& outcome) noexcept;
  void monitor(hal::Nanoseconds now) noexcept;
  void publish() noexcept;
  void note_returned_joints(hal::Nanoseconds now) noexcept;
  void auto_clear_returned(hal::Nanoseconds now) noexcept;
  // Saves `next` as the file's new contents (sequence + 1). Success: recorded_ = next. Failure: the file
  // is marked dirty and the caller decides what recorded_ holds; step() retries a dirty file.
  Status persist(const ErrorJointsContents& next, hal::Nanoseconds now) noexcept;
  void send_notice(const JointManagerNotice& notice, hal::Nanoseconds now) noexcept;
  void flush_notices() noexcept;
  // Dispatches `input` to joint j with its guard facts refreshed; logs the transition or the refusal.
  Status dispatch(std::size_t j, fsm::JointInput input, hal::Nanoseconds now) noexcept;
  void latch_loss(std::size_t j, FaultReason reason, double position_rad, hal::Nanoseconds now) noexcept;
  void emit(const JointEvent& event) const noexcept { ports_.events->on_event(event); }
  void emit_step(std::uint8_t step, JointMask joints, hal::Nanoseconds now) const noexcept;

  JointManagerPorts ports_;
  std::array<Joint, kJointCount> joints_{};
  std::array<JointStatus, kJointCount> status_{};
  RobotSample sample_{};                 // the last snapshot read (lost joints keep their last values)
  JointMask lost_{0};                    // loss latched (file or report) until an operator clears it
  JointMask lost_since_start_{0};        // every loss latched, cleared or not
  JointMask returned_{0};                // lost joints seen answering again (reported once per return)
  bool auto_clear_power_cycled_{false};
  JointMask auto_clear_pending_{0};      // back after a power cycle, to clear once seen reachable
  ErrorJointsContents recorded_;         // what the error-joints file holds (or must hold: file_dirty_)
  bool file_dirty_{false};
  hal::Nanoseconds next_write_retry_{0};
  FixedVector<JointManagerNotice, kMaxDeferredNotices> deferred_notices_;
  FixedVector<JointCommand, kMaxRequestSteps> batch_;  // an all-or-nothing request's steps received so far
  std::uint32_t refused_commands_{0};
  std::uint32_t outcomes_dropped_{0};
  std::uint32_t file_writes_{0};
  std::uint32_t file_write_failures_{0};
};

}  // namespace rescue::app
