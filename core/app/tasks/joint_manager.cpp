#include "core/app/tasks/joint_manager.hpp"

#include <algorithm>
#include <cassert>

#include "drivers/joint/joint_units.hpp"

namespace rescue::app {
namespace {

using fsm::JointInput;
using fsm::JointState;

bool valid_mode(ControlMode mode) noexcept {
  return mode == ControlMode::cyclic_position || mode == ControlMode::cyclic_velocity ||
         mode == ControlMode::cyclic_torque;
}

// A command is a record of the shared segment (the parser's queue): every field that names a
// joint, a kind, an input, a mode or a step must be one the parser writes. Anything else is damage
// (a stray write, a bit flip): the record is refused whole, never used.
bool command_whole(const JointCommand& c) noexcept {
  const bool kind = c.kind == JointCommandKind::dfa_input || c.kind == JointCommandKind::clear_lost ||
                    c.kind == JointCommandKind::clear_lost_moved;
  const bool input = static_cast<std::size_t>(c.input) < fsm::kJointInputCount;
  const bool mode = c.mode == ControlMode::none || valid_mode(c.mode);
  const bool steps = c.steps >= 1 && c.steps <= kMaxRequestSteps && c.step < c.steps;
  return kind && input && mode && steps && (c.joints & ~kAllJoints) == 0;
}

// A report is a record of the segment too (the handler's queue): a joint beyond the robot is damage.
bool report_whole(const LostJointsReport& r) noexcept {
  return ((r.lost | r.back_after_power_cycle) & ~kAllJoints) == 0;
}

JointEvent event(JointEventKind kind, hal::Nanoseconds now) noexcept {
  JointEvent e;
  e.kind = kind;
  e.time = now;
  return e;
}

JointEvent joints_event(JointEventKind kind, JointMask joints, hal::Nanoseconds now) noexcept {
  JointEvent e = event(kind, now);
  e.joints = joints;
  return e;
}

JointEvent joint_event(JointEventKind kind, std::size_t joint, hal::Nanoseconds now) noexcept {
  JointEvent e = event(kind, now);
  e.joint = static_cast<std::uint8_t>(joint);
  return e;
}

}  // namespace

JointManager::JointManager(const JointManagerPorts& ports) noexcept : ports_(ports) {
  assert(ports.reports != nullptr && ports.notices != nullptr && ports.commands != nullptr &&
         ports.samples != nullptr && ports.storage != nullptr && ports.wall_clock != nullptr &&
         ports.events != nullptr && ports.save_requests != nullptr && ports.save_results != nullptr);
  publish();
}

std::array<JointState, kJointCount> JointManager::states() const noexcept {
  std::array<JointState, kJointCount> out{};
  for (std::size_t j = 0; j < kJointCount; ++j) out[j] = joints_[j].machine.state();
  return out;
}

RestoreReport JointManager::restore(hal::Nanoseconds now) noexcept {
  RestoreReport report;
  ErrorJointsLoad load = ports_.storage->load();
  report.file_present = load.file_present;
  const ErrorJointsDecoded& decoded = load.decoded;
  if (!load.file_present && !load.copy_present && decoded.status.error().code == Errc::not_found) {
    emit(event(JointEventKind::file_absent, now));
    return report;
  }
  // The second copy stands in for a file that is damaged, missing or older than it (a save that
  // stopped between the two writes): one damaged file never forgets a loss.
  const bool file_good = load.file_present && decoded.status.ok();
  const bool copy_good = load.copy_present && load.copy.status.ok();
  const bool use_copy = copy_good && (!file_good || load.copy.contents.sequence > decoded.contents.sequence);
  bool rewrite = false;
  bool damaged = false;  // no readable record at all: salvage what passed, hold out the rest
  if (use_copy) {
    report.from_copy = true;
    report.copy_sequence = load.copy.contents.sequence;
    recorded_ = load.copy.contents;
    JointEvent e = event(JointEventKind::file_copy_used, now);
    e.error = load.file_present ? decoded.status.error() : make_error(Errc::not_found, "no such file");
    e.count = load.copy.contents.sequence;
    if (file_good) e.error = Error{};
    emit(e);
    if (load.file_present && !file_good) {
      report.file_status = decoded.status;
      report.records_dropped = decoded.records_rejected;
    }
    rewrite = true;  // both names hold the same record again
  } else {
    report.file_status = load.file_present ? decoded.status
                                           : Status(make_error(Errc::not_found, "the file is missing and its second copy damaged"));
    if (!load.file_present) report.file_present = true;  // what there is (the copy) is damaged
    report.records_dropped = decoded.records_rejected;
    recorded_ = decoded.contents;
    damaged = !report.file_status.ok();
    // A good file whose copy is missing, damaged or older (a save stopped between the two writes, or
    // a file from before the copy existed): the copy is brought level now, not at the next loss.
    if (!damaged && (!copy_good || load.copy.contents.sequence != decoded.contents.sequence)) rewrite = true;
  }
  durable_joints_ = recorded_.joints();
  if (damaged) report.salvaged = recorded_.joints();

  if (load.newer_temporary) {
    take_newer_temporary(load, report, now);
    rewrite = true;
  }
  if (damaged) salvage_damaged_file(report, now);

  for (const LostJointRecord& r : recorded_.records) {
    latch_loss(r.joint, r.reason, drivers::counts_to_rad(r.last_position_counts), now);
    report.restored |= joint_bit(r.joint);
  }
  if (damaged) {
    JointEvent e = joints_event(JointEventKind::file_unusable, report.salvaged, now);
    e.error = report.file_status.error();
    e.count = decoded.records_rejected;
    emit(e);
  }
  if (damaged || (report.from_copy && load.file_present && !file_good)) {
    // Keep the damaged file for post-mortem rather than let the next write destroy it, then store the
    // part that could be trusted (or the copy) under the file's name again.
    if (load.file_present) {
      const Result<std::uint32_t> aside = ports_.storage->set_aside();
      if (aside.ok()) {
        report.set_aside = true;
        report.set_aside_suffix = aside.value();
        JointEvent kept = event(JointEventKind::file_set_aside, now);
        kept.count = aside.value();
        emit(kept);
      }
    }
    rewrite = true;
  }
  if (rewrite && !recorded_.records.empty()) write_at_start_up(now);
  if (report.restored != 0 || decoded.status.ok() || report.from_copy) {
    emit(joints_event(JointEventKind::file_restored, report.restored, now));
  }
  publish();
  return report;
}

// A complete newer temporary file: the last write reached the disk but not its name. Its joints were
// being recorded lost; holding them out is the safe reading (an operator clears them again).
void JointManager::take_newer_temporary(const ErrorJointsLoad& load, RestoreReport& report, hal::Nanoseconds now) noexcept {
  report.newer_temporary = true;
  report.temporary_sequence = load.temporary.sequence;
  for (const LostJointRecord& r : load.temporary.records) {
    if (recorded_.find(r.joint) != nullptr) continue;
    (void)recorded_.records.push_back(r);  // cannot fail: one record per joint at most
    report.from_temporary |= joint_bit(r.joint);
  }
  if (load.temporary.sequence > recorded_.sequence) recorded_.sequence = load.temporary.sequence;
  JointEvent e = joints_event(JointEventKind::file_newer_temporary, report.from_temporary, now);
  e.count = load.temporary.sequence;
  emit(e);
}

// A damaged file's salvage follows the wiring: a joint behind a salvaged lost joint on its branch
// could not be reached either (its own record is the damaged one), so it is recorded lost as well.
void JointManager::salvage_damaged_file(RestoreReport& report, hal::Nanoseconds now) noexcept {
  const JointMask salvaged = recorded_.joints();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const LostJointRecord* found = recorded_.find(j);
    if (found == nullptr || (salvaged & joint_bit(j)) == 0) continue;
    const LostJointRecord upstream = *found;
    const JointMask behind = joints_lost_by_link_failure_at(j) & ~recorded_.joints();
    for (std::size_t k = 0; k < kJointCount; ++k) {
      if ((behind & joint_bit(k)) == 0) continue;
      LostJointRecord r = upstream;  // same loss: its time and cycle; the held position is unknown
      r.joint = static_cast<std::uint8_t>(k);
      r.last_position_counts = 0;
      (void)recorded_.records.push_back(r);  // cannot fail: one record per joint at most
      report.added_behind |= joint_bit(k);
    }
  }
  if (report.added_behind != 0) {
    emit(joints_event(JointEventKind::file_wiring_added, report.added_behind, now));
  }
  // No readable record: which other joints were lost cannot be known, so none of them may enable
  // until the operator clears it by name (its held position unknown: the clear confirms it).
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (recorded_.find(j) != nullptr) continue;
    LostJointRecord r;
    r.joint = static_cast<std::uint8_t>(j);
    r.reason = FaultReason::record_unreadable;
    (void)recorded_.records.push_back(r);  // cannot fail: one record per joint at most
    report.held_unreadable |= joint_bit(j);
  }
  if (report.held_unreadable != 0) {
    emit(joints_event(JointEventKind::file_unreadable_held, report.held_unreadable, now));
  }
}

void JointManager::step(hal::Nanoseconds now) noexcept {
  (void)ports_.samples->read(sample_);  // false: keep the previous snapshot
  // Reports first: the handler queues a drive's return after a power cycle before it publishes the
  // sample that shows the joint reachable, so a returned joint's note knows whether it is cleared
  // automatically (no "stays in Error" line before "cleared automatically").
  LostJointsReport report;
  for (std::size_t n = 0; n < kMaxReportsPerStep && ports_.reports->try_receive(report); ++n) {
    handle_report(report, now);
  }
  note_returned_joints(now);
  collect_file_results(now);
  auto_clear_returned(now);
  flush_notices();
  flush_outcome();
  continue_request(now);  // the steps of an all-or-nothing request behind a clear, once it is durable
  // The joint handle queue in order: the commands behind a clear wait for its durable write (a reset
  // after a clear needs the loss unlatched), and none is taken while an outcome waits for room.
  JointCommand command;
  for (std::size_t n = 0; n < kMaxCommandsPerStep && !clear_.active && !outcome_deferred_ &&
                          ports_.commands->try_receive(command);
       ++n) {
    receive_command(command, now);
  }
  send_file_write(now);
  collect_file_results(now);  // a write already durable is answered in this period
  monitor(now);
  publish();
  if (ports_.joint_status != nullptr) ports_.joint_status->write(published_status(status_));
}

double JointManager::offset_from_held(std::size_t j) const noexcept {
  const auto* const it = std::find_if(recorded_.records.begin(), recorded_.records.end(),
                               [j](const LostJointRecord& r) { return r.joint == j; });
  if (it == recorded_.records.end()) return 0.0;  // no held position recorded: nothing to compare
  return sample_[j].position_rad - drivers::counts_to_rad(it->last_position_counts);
}

void JointManager::auto_clear_returned(hal::Nanoseconds now) noexcept {
  auto_clear_pending_ &= lost_;
  if (clear_.active) return;  // one clear at a time: these wait for the one in flight
  JointMask ready = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((auto_clear_pending_ & joint_bit(j)) != 0 && sample_[j].reachable) ready |= joint_bit(j);
  }
  if (ready == 0) return;
  auto_clear_pending_ &= ~ready;
  // Refusals (e.g. moved from the held position) are logged; the reset follows the durable write.
  (void)clear_lost_joints(ready, now, 0, true);
}

void JointManager::note_returned_joints(hal::Nanoseconds now) noexcept {
  // A lost joint that answers again (its slave was brought back, e.g. by the master's online
  // recovery) is reported once per return, with whether it still stands at its held position.
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointMask bit = joint_bit(j);
    if ((lost_ & bit) == 0 || !sample_[j].reachable) {
      returned_ &= ~bit;
      continue;
    }
    if ((returned_ & bit) != 0) continue;
    returned_ |= bit;
    const double offset = offset_from_held(j);
    const bool moved = offset > kHeldPositionToleranceRad || offset < -kHeldPositionToleranceRad;
    if (!moved && (auto_clear_pending_ & bit) != 0) continue;  // auto_clear_returned() says it, this step
    JointEvent e = joint_event(moved ? JointEventKind::lost_joint_moved : JointEventKind::lost_joint_returned, j, now);
    e.fault.value = offset;
    e.fault.limit = kHeldPositionToleranceRad;
    emit(e);
  }
}

// Paper section IV-C, steps 1-5; the handler does step 6 when it reads the answer.
void JointManager::handle_report(const LostJointsReport& report, hal::Nanoseconds now) noexcept {
  if (!report_whole(report)) {
    ++damaged_records_;
    return;
  }
  if (report.lost == 0) {
    // A drive back after a power cycle: cleared and reset (once it is seen reachable) only when
    // the configuration says so.
    if (auto_clear_power_cycled_) auto_clear_pending_ |= report.back_after_power_cycle & lost_;
    return;
  }
  const JointMask reported = report.lost & kAllJoints;
  const JointMask fresh = reported & ~lost_;
  emit_step(1, reported, now);

  // Step 2: the last state the handler published for them (it leaves an unreachable joint's last values).
  std::array<double, kJointCount> last_position{};
  for (std::size_t j = 0; j < kJointCount; ++j) last_position[j] = sample_[j].position_rad;
  emit_step(2, fresh, now);

  // Step 3: the file lists every joint lost so far, not only this report's, so no joint's record is
  // ever dropped by a later write. The storage worker writes it (send_file_write); steps 3 and 4
  // complete when it reports the write durable (on_durable).
  const JointMask to_record = reported & ~recorded_.joints();
  if (to_record != 0) {
    const std::int64_t wall = ports_.wall_clock->unix_time_ns();
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((to_record & joint_bit(j)) == 0) continue;
      LostJointRecord r;
      r.joint = static_cast<std::uint8_t>(j);
      r.reason = FaultReason::comm_lost;
      r.last_position_counts = drivers::rad_to_counts(last_position[j]);  // the file keeps the encoder's count
      r.time_unix_ns = wall;
      r.cycle = report.cycle;
      (void)recorded_.records.push_back(r);  // cannot fail: one record per joint at most
    }
    ++intent_version_;
  }
  if (clear_.active && (clear_.joints & reported) != 0) {
    // Lost again while its clear is being written: it stays lost, and the next write keeps it.
    clear_.joints &= ~reported;
    ++intent_version_;
  }
  // Step 4: answer now when the file already holds them durably, else once it does.
  if ((reported & ~durable_joints_) == 0 && !file_dirty()) {
    answer(reported, report.cycle, Error{}, now);
  } else if (!answers_.push_back(PendingAnswer{reported, report.cycle, intent_version_, false})) {
    PendingAnswer& last = answers_.back();  // full: folded into the last one, no joint forgotten
    last.joints |= reported;
    last.cycle = report.cycle;
    last.version = intent_version_;
  }

  // Step 5: comm_lost into each DFA at once (safety does not wait for the disk).
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((fresh & joint_bit(j)) != 0) latch_loss(j, FaultReason::comm_lost, last_position[j], now);
  }
  emit_step(5, fresh, now);
}

// Steps 3 and 4 for `joints`: with `file` ok, the file holds them durably; else the answer says why
// it does not yet (the write is retried, and answered again once durable).
void JointManager::answer(JointMask joints, std::uint64_t cycle, const Error& file, hal::Nanoseconds now) noexcept {
  if (file.code == Errc::ok) emit_step(3, joints, now);
  JointManagerNotice notice;
  notice.kind = NoticeKind::lost_joints_recorded;
  notice.joints = joints;
  notice.cycle = cycle;
  notice.file_status = file.code;
  send_notice(notice, now);
  JointEvent e = joints_event(JointEventKind::reconfiguration_step, joints, now);
  e.step = 4;
  e.error = file;
  emit(e);
}

void JointManager::latch_loss(std::size_t j, FaultReason reason, double position_rad, hal::Nanoseconds now) noexcept {
  lost_ |= joint_bit(j);
  lost_since_start_ |= joint_bit(j);
  Joint& joint = joints_[j];
  joint.held_position_rad = position_rad;
  joint.fault = JointFault{reason, 0.0, 0.0};
  JointEvent e = joint_event(JointEventKind::fault, j, now);
  e.fault = joint.fault;
  emit(e);
  (void)dispatch(j, JointInput::comm_lost, now);
}

void JointManager::apply_command(const JointCommand& command, hal::Nanoseconds now) noexcept {
  JointCommandOutcome outcome;
  outcome.request = command.request;
  outcome.input = command.input;
  outcome.kind = command.kind;
  const auto refuse = [&outcome, &command, this](std::size_t j, CommandRefusal why, protocol::JointRefusal note) noexcept {
    if (outcome.refused == 0) {
      outcome.first_reason = why;
      outcome.first_joint = static_cast<std::uint8_t>(j);
      outcome.first_state = joints_[j].machine.state();
    }
    outcome.refused |= joint_bit(j);
    outcome.notes[j] = JointRefusalNote{note, joints_[j].machine.state(), command.input};
  };
  if (command.kind == JointCommandKind::clear_lost || command.kind == JointCommandKind::clear_lost_moved) {
    const JointMask joints = command.joints & kAllJoints;
    const JointMask confirmed = command.kind == JointCommandKind::clear_lost_moved ? joints : 0;
    // Each joint's reason, judged before the clear starts (a refused joint is named with its own).
    std::array<protocol::JointRefusal, kJointCount> why{};
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((joints & joint_bit(j)) != 0) why[j] = clear_refusal(j, lost_, (confirmed & joint_bit(j)) != 0);
    }
    (void)clear_lost_joints(joints, now, confirmed);  // each refusal is logged
    const JointMask accepted = clear_.active ? clear_.requested : 0;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((joints & ~accepted & joint_bit(j)) == 0) continue;
      refuse(j, CommandRefusal::clear_refused,
             why[j] != protocol::JointRefusal::none ? why[j] : protocol::JointRefusal::file_not_written);
    }
    if (accepted == 0) {
      ++refused_commands_;
      report_outcome(outcome);
      return;
    }
    clear_.has_outcome = true;  // reported when the write is durable (finish_clear)
    clear_.outcome = outcome;
    return;
  }
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((command.joints & joint_bit(j)) == 0) continue;
    // Preconditions of the manager, before the table: a mode to select, and a joint to talk to.
    Error precondition{};
    CommandRefusal why = CommandRefusal::none;
    if (command.input == JointInput::select_mode && !valid_mode(command.mode)) {
      precondition = make_error(Errc::invalid_argument, "select_mode needs CSP, CSV or CST",
                                static_cast<std::uint32_t>(static_cast<std::uint8_t>(command.mode)));
      why = CommandRefusal::bad_mode;
    } else if (!sample_[j].reachable && command.input != JointInput::disable && command.input != JointInput::reset) {
      precondition = make_error(Errc::refused, "joint not reachable");
      why = CommandRefusal::unreachable;
    }
    if (precondition.code != Errc::ok) {
      ++refused_commands_;
      refuse(j, why, why == CommandRefusal::bad_mode ? protocol::JointRefusal::bad_mode : protocol::JointRefusal::unreachable);
      JointEvent e = joint_event(JointEventKind::refused, j, now);
      e.from = joints_[j].machine.state();
      e.input = command.input;
      e.error = precondition;
      emit(e);
      continue;
    }
    joints_[j].context.requested_mode = command.mode;
    if (dispatch(j, command.input, now).ok()) {
      outcome.applied |= joint_bit(j);
    } else {  // a refused input leaves the state as it was (refuse() reads the state: unchanged)
      ++refused_commands_;
      refuse(j, CommandRefusal::state_machine, protocol::JointRefusal::state_machine);
    }
  }
  report_outcome(outcome);
}

void JointManager::receive_command(const JointCommand& command, hal::Nanoseconds now) noexcept {
  if (!command_whole(command)) {  // no outcome: its request id is not to be trusted either
    ++damaged_records_;
    return;
  }
  if (!command.all_or_nothing || command.request == 0 || command.steps <= 1 || command.steps > kMaxRequestSteps) {
    batch_.clear();
    if (command.all_or_nothing && command.request != 0 && command.steps <= 1) {
      (void)batch_.push_back(command);
      apply_request(now);
      return;
    }
    apply_command(command, now);
    return;
  }
  // The steps of one request follow each other on the queue; a partial request whose rest never came
  // (the parser's queue was full: it answers busy) is dropped by the next one.
  if (!batch_.empty() && batch_[0].request != command.request) batch_.clear();
  if (command.step != batch_.size()) {
    batch_.clear();
    return;
  }
  (void)batch_.push_back(command);
  if (batch_.size() < command.steps) return;  // the rest follows
  apply_request(now);
}

protocol::JointRefusal JointManager::clear_refusal(std::size_t j, JointMask lost, bool confirmed_moved) const noexcept {
  if ((lost & joint_bit(j)) == 0) return protocol::JointRefusal::not_lost;
  if (!sample_[j].reachable) return protocol::JointRefusal::still_unreachable;
  const double offset = offset_from_held(j);
  if (!confirmed_moved && (offset > kHeldPositionToleranceRad || offset < -kHeldPositionToleranceRad)) {
    return protocol::JointRefusal::moved;
  }
  return protocol::JointRefusal::none;
}

protocol::JointRefusal JointManager::dfa_refusal(std::size_t j, const JointCommand& command, JointMask lost,
                                                 const fsm::JointStatusMachine& machine,
                                                 fsm::JointContext& context) const noexcept {
  if (command.input == JointInput::select_mode && !valid_mode(command.mode)) return protocol::JointRefusal::bad_mode;
  if (!sample_[j].reachable && command.input != JointInput::disable && command.input != JointInput::reset) {
    return protocol::JointRefusal::unreachable;
  }
  // The guard's facts as dispatch() sets them.
  JointFault present = check_drive_fault(sample_[j]);
  if (!present.active()) present = check_actual_limits(sample_[j], kJoints[j]);
  context.reachable = sample_[j].reachable;
  context.fault_present = sample_[j].reachable && present.active();
  context.loss_latched = (lost & joint_bit(j)) != 0;
  context.requested_mode = command.mode;
  context.actual_position_rad = sample_[j].position_rad;
  return machine.accepts(context, command.input) ? protocol::JointRefusal::none : protocol::JointRefusal::state_machine;
}

void JointManager::continue_request(hal::Nanoseconds now) noexcept {
  // A clear is durable only once the storage worker has written it: the steps behind it wait.
  if (!batch_running_) return;
  while (batch_next_ < batch_.size() && !clear_.active) apply_command(batch_[batch_next_++], now);
  if (batch_next_ >= batch_.size()) {
    batch_.clear();
    batch_next_ = 0;
    batch_running_ = false;
  }
}

void JointManager::apply_request(hal::Nanoseconds now) noexcept {
  // The trial: every step on copies of the machines, in order, as the real application would go.
  std::array<fsm::JointStatusMachine, kJointCount> machines{};
  std::array<fsm::JointContext, kJointCount> contexts{};
  for (std::size_t j = 0; j < kJointCount; ++j) {
    machines[j] = joints_[j].machine;
    contexts[j] = joints_[j].context;
  }
  JointMask lost = lost_;
  JointCommandOutcome refusal;
  refusal.request = batch_[0].request;
  refusal.input = batch_[0].input;
  refusal.kind = batch_[0].kind;
  for (const JointCommand& command : batch_) {
    const bool clear = command.kind != JointCommandKind::dfa_input;
    JointMask cleared = 0;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((command.joints & joint_bit(j)) == 0 || (refusal.refused & joint_bit(j)) != 0) continue;
      const protocol::JointRefusal why =
          clear ? clear_refusal(j, lost, command.kind == JointCommandKind::clear_lost_moved)
                : dfa_refusal(j, command, lost, machines[j], contexts[j]);
      if (why != protocol::JointRefusal::none) {
        if (refusal.refused == 0) {
          refusal.first_reason = why == protocol::JointRefusal::state_machine ? CommandRefusal::state_machine
                                 : why == protocol::JointRefusal::unreachable ? CommandRefusal::unreachable
                                 : why == protocol::JointRefusal::bad_mode    ? CommandRefusal::bad_mode
                                                                              : CommandRefusal::clear_refused;
          refusal.first_joint = static_cast<std::uint8_t>(j);
          refusal.first_state = machines[j].state();
          refusal.input = command.input;
          refusal.kind = command.kind;
        }
        refusal.refused |= joint_bit(j);
        refusal.notes[j] = JointRefusalNote{why, machines[j].state(), command.input};
        continue;
      }
      if (clear) {
        cleared |= joint_bit(j);
        contexts[j].loss_latched = false;
      } else {
        (void)machines[j].dispatch(contexts[j], command.input);
      }
    }
    lost &= ~cleared;
  }
  if (refusal.refused == 0) {
    batch_next_ = 0;
    batch_running_ = true;
    continue_request(now);
    return;
  }
  // Refused: nothing changes. The log names each blocking joint; the parser gets one outcome per step.
  ++refused_commands_;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((refusal.refused & joint_bit(j)) == 0) continue;
    JointEvent e = joint_event(JointEventKind::refused, j, now);
    e.from = refusal.notes[j].state;
    e.input = refusal.notes[j].input;
    e.error = make_error(Errc::refused, protocol::to_string(refusal.notes[j].why));
    emit(e);
  }
  report_outcome(refusal);
  for (std::size_t s = 1; s < batch_.size(); ++s) {
    JointCommandOutcome nothing;
    nothing.request = batch_[s].request;
    nothing.input = batch_[s].input;
    nothing.kind = batch_[s].kind;
    report_outcome(nothing);
  }
  batch_.clear();
}

void JointManager::report_outcome(const JointCommandOutcome& outcome) noexcept {
  if (outcome.request == 0 || ports_.outcomes == nullptr) return;
  if (!outcome_deferred_ && ports_.outcomes->try_send(outcome)) return;
  // Full: kept and resent; no further command is applied until it went (so there is only ever one).
  deferred_outcome_ = outcome;
  outcome_deferred_ = true;
  ++outcomes_deferred_;
}

void JointManager::flush_outcome() noexcept {
  if (outcome_deferred_ && ports_.outcomes != nullptr && ports_.outcomes->try_send(deferred_outcome_)) {
    outcome_deferred_ = false;
  }
}

Status JointManager::dispatch(std::size_t j, JointInput input, hal::Nanoseconds now) noexcept {
  Joint& joint = joints_[j];
  // The guard's facts, current at the instant of the dispatch.
  JointFault present = check_drive_fault(sample_[j]);
  if (!present.active()) present = check_actual_limits(sample_[j], kJoints[j]);
  joint.context.reachable = sample_[j].reachable;
  joint.context.fault_present = sample_[j].reachable && present.active();
  joint.context.loss_latched = (lost_ & joint_bit(j)) != 0;
  // The position an aligning action takes (set_reference, enable, disable): where the joint is now.
  if (sample_[j].reachable) joint.context.actual_position_rad = sample_[j].position_rad;

  const JointState from = joint.machine.state();
  const Status status = joint.machine.dispatch(joint.context, input);
  JointEvent e = joint_event(status.ok() ? JointEventKind::transition : JointEventKind::refused, j, now);
  e.from = from;
  e.to = joint.machine.state();
  e.input = input;
  if (!status.ok()) e.error = status.error();
  if (status.ok() && input == JointInput::reset) joint.fault = JointFault{};  // the fault is history now
  emit(e);
  return status;
}

void JointManager::monitor(hal::Nanoseconds now) noexcept {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointSample& s = sample_[j];
    // Lost joints have no fresh data, and an unreachable joint's stale values are not judged: losses
    // come from the handler's report.
    if ((lost_ & joint_bit(j)) != 0 || !s.reachable) continue;
    Joint& joint = joints_[j];
    const JointState state = joint.machine.state();
    if (state == JointState::error) continue;
    JointFault f = check_drive_fault(s);
    if (!f.active()) f = check_actual_limits(s, kJoints[j]);
    if (!f.active() && state == JointState::enabled) f = check_reference_limits(s, kJoints[j]);
    if (!f.active()) continue;
    joint.fault = f;
    JointEvent e = joint_event(JointEventKind::fault, j, now);
    e.fault = f;
    emit(e);
    (void)dispatch(j, JointInput::fault, now);
  }
}

Status JointManager::clear_lost_joint(std::size_t joint, hal::Nanoseconds now) noexcept {
  if (joint >= kJointCount) {
    const Error refusal = make_error(Errc::invalid_argument, "no such joint", static_cast<std::uint32_t>(joint));
    JointEvent e = joint_event(JointEventKind::operator_clear_refused, kNoJoint, now);
    e.error = refusal;
    emit(e);
    return refusal;
  }
  return clear_lost_joints(joint_bit(joint), now);
}

Status JointManager::clear_lost_joints(JointMask joints, hal::Nanoseconds now, JointMask confirmed_moved,
                                       bool automatic) noexcept {
  // Each joint is judged on its own; the ones that may be cleared leave the file in one durable write.
  Error first_refusal{};
  JointMask accepted = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) == 0) continue;
    Error refusal{};
    if (clear_.active) {
      refusal = make_error(Errc::refused, "another clear is being written", static_cast<std::uint32_t>(j));
    } else if ((lost_ & joint_bit(j)) == 0) {
      refusal = make_error(Errc::refused, "joint is not recorded as lost", static_cast<std::uint32_t>(j));
    } else if (!sample_[j].reachable) {
      refusal = make_error(Errc::refused, "joint still unreachable: repair it first", static_cast<std::uint32_t>(j));
    } else if ((confirmed_moved & joint_bit(j)) == 0 &&
               (offset_from_held(j) > kHeldPositionToleranceRad || offset_from_held(j) < -kHeldPositionToleranceRad)) {
      refusal = make_error(Errc::refused, "position differs from the held position in the file: confirm the clear",
                           static_cast<std::uint32_t>(j));
    }
    if (refusal.code == Errc::ok) {
      accepted |= joint_bit(j);
      continue;
    }
    if (first_refusal.code == Errc::ok) first_refusal = refusal;
    JointEvent e = joint_event(JointEventKind::operator_clear_refused, j, now);
    e.error = refusal;
    emit(e);
  }
  if (accepted == 0) {
    return first_refusal.code != Errc::ok ? Status(first_refusal)
                                          : Status(make_error(Errc::invalid_argument, "no joint to clear"));
  }

  // Durable first: a clear that is not on disk did not happen. The joints leave the file with the
  // next write; finish_clear unlatches them once the worker reports it durable.
  clear_ = PendingClear{};
  clear_.active = true;
  clear_.requested = accepted;
  clear_.joints = accepted;
  clear_.automatic = automatic;
  clear_.version = ++intent_version_;
  if (first_refusal.code != Errc::ok) return first_refusal;  // the others are being cleared
  return Status::success();
}

void JointManager::finish_clear(const Error& file, hal::Nanoseconds now) noexcept {
  const JointMask cleared = file.code == Errc::ok ? clear_.joints : 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((clear_.requested & ~cleared & joint_bit(j)) == 0) continue;
    JointEvent e = joint_event(JointEventKind::operator_clear_refused, j, now);
    e.error = file.code != Errc::ok ? file
                                    : make_error(Errc::refused, "lost again before the clear was written",
                                                 static_cast<std::uint32_t>(j));
    emit(e);
  }
  if (cleared != 0) {
    ErrorJointsContents kept;
    kept.sequence = recorded_.sequence;
    for (const LostJointRecord& r : recorded_.records) {
      if ((cleared & joint_bit(r.joint)) == 0) (void)kept.records.push_back(r);
    }
    recorded_ = kept;
    lost_ &= ~cleared;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((cleared & joint_bit(j)) == 0) continue;
      joints_[j].context.loss_latched = false;
      emit(joint_event(clear_.automatic ? JointEventKind::auto_cleared : JointEventKind::operator_cleared, j, now));
    }
    JointManagerNotice notice;
    notice.kind = NoticeKind::joints_cleared;
    notice.joints = cleared;
    send_notice(notice, now);
    if (clear_.automatic) {
      for (std::size_t j = 0; j < kJointCount; ++j) {
        if ((cleared & joint_bit(j)) != 0) (void)dispatch(j, JointInput::reset, now);
      }
    }
  }
  if (clear_.has_outcome) {
    JointCommandOutcome outcome = clear_.outcome;
    outcome.applied |= cleared;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((clear_.requested & ~cleared & joint_bit(j)) == 0) continue;
      if (outcome.refused == 0) {
        outcome.first_reason = CommandRefusal::clear_refused;
        outcome.first_joint = static_cast<std::uint8_t>(j);
        outcome.first_state = joints_[j].machine.state();
      }
      outcome.refused |= joint_bit(j);
      outcome.notes[j] = JointRefusalNote{protocol::JointRefusal::file_not_written, joints_[j].machine.state(), outcome.input};
    }
    if (outcome.refused != 0) ++refused_commands_;
    report_outcome(outcome);
  }
  clear_ = PendingClear{};
  publish();
}

// Sends what the file must hold now (every joint recorded lost, less those whose clear is pending)
// when it changed, no write is in flight, and a failed write's retry period has passed.
void JointManager::send_file_write(hal::Nanoseconds now) noexcept {
  if (in_flight_ || !file_dirty() || now < next_write_retry_) return;
  const JointMask clearing = clear_.active ? clear_.joints : 0;
  ErrorJointsContents next;
  next.sequence = recorded_.sequence + 1;
  for (const LostJointRecord& r : recorded_.records) {
    if ((clearing & joint_bit(r.joint)) == 0) (void)next.records.push_back(r);
  }
  if (!ports_.save_requests->try_send(ErrorJointsSaveRequest::of(next))) return;  // cannot be full: one in flight
  in_flight_ = true;
  in_flight_version_ = intent_version_;
  in_flight_sequence_ = next.sequence;
  in_flight_joints_ = next.joints();
}

void JointManager::collect_file_results(hal::Nanoseconds now) noexcept {
  ErrorJointsSaveResult result;
  while (ports_.save_results->try_receive(result)) {
    if (!in_flight_ || result.sequence != in_flight_sequence_) continue;  // not ours (cannot happen)
    in_flight_ = false;
    if (result.error.code == Errc::ok) {
      on_durable(now);
    } else {
      on_write_failed(result.error, now);
    }
  }
}

void JointManager::on_durable(hal::Nanoseconds now) noexcept {
  durable_version_ = in_flight_version_;
  durable_joints_ = in_flight_joints_;
  recorded_.sequence = in_flight_sequence_;
  rewrite_ = false;
  ++file_writes_;
  JointEvent e = event(JointEventKind::file_written, now);
  e.joints = durable_joints_;
  e.count = in_flight_sequence_;
  emit(e);
  while (!answers_.empty() && answers_[0].version <= durable_version_) {
    answer(answers_[0].joints, answers_[0].cycle, Error{}, now);
    answers_.erase_at(0);
  }
  if (clear_.active && clear_.version <= durable_version_) finish_clear(Error{}, now);
}

void JointManager::on_write_failed(const Error& error, hal::Nanoseconds now) noexcept {
  next_write_retry_ = now + kWriteRetryPeriod;
  ++file_write_failures_;
  JointEvent e = event(JointEventKind::file_write_failed, now);
  e.error = error;
  emit(e);
  // The handler hears that the file does not hold them yet (once); it is answered again when it does.
  for (PendingAnswer& a : answers_) {
    if (a.version > in_flight_version_ || a.told_failure) continue;
    a.told_failure = true;
    answer(a.joints, a.cycle, error, now);
  }
  if (clear_.active && clear_.version <= in_flight_version_) finish_clear(error, now);  // the joints stay lost
  // Nothing left to write when the file already holds every joint recorded lost (a refused clear).
  if (recorded_.joints() == durable_joints_ && !rewrite_ && answers_.empty() && !clear_.active) {
    durable_version_ = intent_version_;
  }
}

void JointManager::write_at_start_up(hal::Nanoseconds now) noexcept {
  ErrorJointsContents numbered = recorded_;
  numbered.sequence = recorded_.sequence + 1;
  const Status status = ports_.storage->save(numbered);
  if (status.ok()) {
    recorded_ = numbered;
    durable_joints_ = recorded_.joints();
    ++file_writes_;
    JointEvent e = event(JointEventKind::file_written, now);
    e.joints = recorded_.joints();
    e.count = recorded_.sequence;
    emit(e);
    return;
  }
  // The first periods send it to the storage worker (retried like any failed write).
  rewrite_ = true;
  ++intent_version_;
  ++file_write_failures_;
  JointEvent e = event(JointEventKind::file_write_failed, now);
  e.error = status.error();
  emit(e);
}

void JointManager::send_notice(const JointManagerNotice& notice, hal::Nanoseconds now) noexcept {
  if (deferred_notices_.empty() && ports_.notices->try_send(notice)) return;
  // Keep it (in order) and resend next step; when even the reserve is full, fold it into the last
  // one of its kind so no joint is forgotten.
  if (!deferred_notices_.push_back(notice)) {
    JointManagerNotice& last = deferred_notices_.back();
    last.joints |= notice.joints;
    if (notice.file_status != Errc::ok) last.file_status = notice.file_status;
  }
  JointEvent e = event(JointEventKind::notice_deferred, now);
  e.joints = notice.joints;
  emit(e);
}

void JointManager::flush_notices() noexcept {
  while (!deferred_notices_.empty() && ports_.notices->try_send(deferred_notices_[0])) deferred_notices_.erase_at(0);
}

void JointManager::emit_step(std::uint8_t step, JointMask joints, hal::Nanoseconds now) const noexcept {
  JointEvent e = joints_event(JointEventKind::reconfiguration_step, joints, now);
  e.step = step;
  emit(e);
}

void JointManager::publish() noexcept {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const Joint& joint = joints_[j];
    JointStatus& s = status_[j];
    s.state = joint.machine.state();
    s.mode = joint.context.mode;
    s.drive_enabled = joint.context.drive_enabled;
    s.lost = (lost_ & joint_bit(j)) != 0;
    s.reference_position_rad = joint.context.reference_position_rad;
    s.held_position_rad = joint.held_position_rad;
    s.fault = joint.fault;
  }
  if (ports_.demand == nullptr) return;
  RobotDemand demand{};
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointStatus& s = status_[j];
    demand[j].enable = s.drive_enabled && !s.lost;
    demand[j].mode = static_cast<std::int8_t>(s.mode);
    demand[j].position_ref_rad = s.reference_position_rad;
  }
  ports_.demand->publish(demand);
}

}  // namespace rescue::app
