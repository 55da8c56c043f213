// The joint manager task (design brief sections 3, 5, 6; paper III-B and IV-C): one joint status DFA
// per joint, limit monitoring, and the reconfiguration procedure after damage.
//
// It runs as a high-priority periodic task (CPU thread 2). Everything it talks to is an interface
// (JointManagerPorts), so the same code runs in the firmware (shared-memory queues and snapshots),
// on threads of one process, and in tests on virtual time. It holds no locks and never waits, not even
// for the disk: the durable write of the error-joints file runs in the storage worker
// (error_joints_worker.hpp, a thread at normal priority), fed by a bounded queue. The period sends the
// file's new contents there and goes on checking limits and driving the state machines; the write's
// outcome comes back on a second queue. The EtherCAT handler only queues a report and reads the
// answer later (core/app/tasks/lost_joint_tracker.hpp), so it never waits either.
//
// Per period, step(now):
//   1. read the handler's latest joint values (one consistent snapshot);
//   2. take the storage worker's outcomes: a durable write completes reconfiguration steps 3-4 (the
//      answer to the handler) and operator clears; a failed one is reported and retried;
//   3. reconfigure for each lost-joints report (paper steps 1, 2 and 5 at once: report, read last
//      state, mark comm_lost; the file's new contents go to the worker);
//   4. resend deferred notices and outcomes;
//   5. apply queued joint commands (the message parser's joint handle queue) to the DFAs; a clear
//      waits for its durable write, and the commands behind it wait in the queue;
//   6. send the file's new contents to the worker when they changed and no write is in flight (a
//      failed write: at most once per kWriteRetryPeriod), and take an outcome that is already there;
//   7. limit monitoring: drive fault, actual position/velocity/torque, and for Enabled joints the
//      commanded values -> `fault` with the reason recorded;
//   8. publish each joint's status (statuses(); through its port joint_status) and its drive demand.
// Bounded: at most kMaxReportsPerStep reports and kMaxCommandsPerStep commands per step. No heap.
#pragma once

#include <array>
#include <cstdint>

#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/error_joints_worker.hpp"
#include "core/app/tasks/joint_events.hpp"
#include "core/app/links/joint_messages.hpp"
#include "core/app/links/joint_sample_source.hpp"
#include "core/robot/error_joints_file.hpp"
#include "core/containers/fixed_vector.hpp"
#include "core/robot/joint_limits.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/concurrency/seqlock.hpp"
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
  ErrorJointsStorage* storage;                 // the error-joints file at start-up (restore(), never step())
  hal::WallClock* wall_clock;                  // Unix time for the file's records
  JointEventSink* events;                      // what happened, for the log
  JointDemandSink* demand{nullptr};            // its drive demand, after every step (nullptr: not published)
  MessageSink<JointCommandOutcome>* outcomes{nullptr};  // to the message parser (commands with a request id)
  // The storage worker (error_joints_worker.hpp): the file's new contents out, the write's outcome back.
  MessageSink<ErrorJointsSaveRequest>* save_requests{nullptr};
  MessageSource<ErrorJointsSaveResult>* save_results{nullptr};
  // Each joint's status (published_status(statuses())), after every step (nullptr: not published):
  // the socket handler's, the message parser's and the RC tasks'.
  Seqlock<RobotJointStatus>* joint_status{nullptr};
};

// JointStatus, what it publishes per joint, is in core/app/links/joint_messages.hpp.

struct RestoreReport {
  JointMask restored{0};        // joints put in Error from the file (all of the masks below)
  bool file_present{false};
  Status file_status;           // success, or why the file (or part of it) was not used
  std::uint32_t records_dropped{0};
  JointMask salvaged{0};        // damaged file: the joints of the records that passed their checks
  JointMask added_behind{0};    // damaged file: joints behind a salvaged one on its branch (unreachable too)
  JointMask held_unreadable{0}; // no readable record (file and copy): every other joint, held until cleared by name
  bool from_copy{false};        // the second copy was used (the file damaged, missing or older)
  std::uint64_t copy_sequence{0};
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
  static constexpr std::size_t kMaxPendingAnswers = 8;
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
  // the joint stays in Error until a `reset` command. Success means accepted: the clear completes
  // (clear_pending() false, the joint no longer lost) once the storage worker made the file durable.
  Status clear_lost_joint(std::size_t joint, hal::Nanoseconds now) noexcept;
  // The same for a set of joints (the operator's `clear_lost` command): each joint is judged alone and
  // logged; those that may be cleared leave the file in one write. The first refusal is returned.
  // One clear at a time: refused while another one's write is in flight.
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
  // Commands and lost-joint reports refused as damaged records of the segment (a kind, input, mode
  // or step no writer writes, a joint beyond the robot): nothing applied, nothing recorded.
  std::uint32_t damaged_records() const noexcept { return damaged_records_; }
  std::uint32_t file_writes() const noexcept { return file_writes_; }
  std::uint32_t file_write_failures() const noexcept { return file_write_failures_; }
  // The file does not hold yet what memory holds (a write in flight, failed, or not yet sent).
  bool file_dirty() const noexcept { return intent_version_ != durable_version_; }
  bool write_in_flight() const noexcept { return in_flight_; }
  bool clear_pending() const noexcept { return clear_.active; }
  // An outcome the full queue could not take: kept, resent, and no command is applied meanwhile.
  std::uint32_t outcomes_deferred() const noexcept { return outcomes_deferred_; }

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
  // The checked request's next steps, each once no clear is being written.
  void continue_request(hal::Nanoseconds now) noexcept;
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
  // restore() only (start-up, before any period): saves recorded_ synchronously (sequence + 1).
  void write_at_start_up(hal::Nanoseconds now) noexcept;
  // restore()'s parts: a newer complete temporary file's joints held out; a damaged file's salvage
  // (the joints behind a salvaged loss on its branch, and every other joint held until cleared).
  void take_newer_temporary(const ErrorJointsLoad& load, RestoreReport& report, hal::Nanoseconds now) noexcept;
  void salvage_damaged_file(RestoreReport& report, hal::Nanoseconds now) noexcept;
  // The storage worker's side (steps 2 and 6 of the period).
  void collect_file_results(hal::Nanoseconds now) noexcept;
  void send_file_write(hal::Nanoseconds now) noexcept;
  void on_durable(hal::Nanoseconds now) noexcept;
  void on_write_failed(const Error& error, hal::Nanoseconds now) noexcept;
  void answer(JointMask joints, std::uint64_t cycle, const Error& file, hal::Nanoseconds now) noexcept;
  void finish_clear(const Error& file, hal::Nanoseconds now) noexcept;
  void flush_outcome() noexcept;
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
  // The error-joints file. recorded_: every joint recorded lost (a joint being cleared stays in it until
  // its clear is durable); its sequence is the file's on disk. Each change of what the file must hold
  // is a new version; the worker makes versions durable, one write in flight at a time.
  ErrorJointsContents recorded_;
  std::uint64_t intent_version_{0};
  std::uint64_t durable_version_{0};
  bool in_flight_{false};
  std::uint64_t in_flight_version_{0};
  std::uint64_t in_flight_sequence_{0};
  JointMask in_flight_joints_{0};
  JointMask durable_joints_{0};          // the joints the file holds durably
  bool rewrite_{false};                  // restore()'s rewrite failed: write even if the joints match
  hal::Nanoseconds next_write_retry_{0};
  // Reconfiguration step 4, waiting for the write that holds the joints (version).
  struct PendingAnswer {
    JointMask joints{0};
    std::uint64_t cycle{0};
    std::uint64_t version{0};
    bool told_failure{false};
  };
  FixedVector<PendingAnswer, kMaxPendingAnswers> answers_;
  // The clear waiting for its write: `joints` leave the file with version `version`.
  struct PendingClear {
    bool active{false};
    JointMask requested{0};  // accepted when asked
    JointMask joints{0};     // still to clear (a joint lost again meanwhile is not)
    bool automatic{false};
    bool has_outcome{false};
    JointCommandOutcome outcome{};
    std::uint64_t version{0};
  };
  PendingClear clear_{};
  FixedVector<JointManagerNotice, kMaxDeferredNotices> deferred_notices_;
  FixedVector<JointCommand, kMaxRequestSteps> batch_;  // an all-or-nothing request's steps received so far
  std::size_t batch_next_{0};      // its next step to apply (a clear's durable write holds the rest)
  bool batch_running_{false};      // checked and being applied
  JointCommandOutcome deferred_outcome_{};
  bool outcome_deferred_{false};
  std::uint32_t refused_commands_{0};
  std::uint32_t damaged_records_{0};
  std::uint32_t outcomes_deferred_{0};
  std::uint32_t file_writes_{0};
  std::uint32_t file_write_failures_{0};
};

}  // namespace rescue::app
