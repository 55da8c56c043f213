#include "core/app/tasks/message_parser.hpp"

#include <bitset>
#include <cstdio>
#include <cstring>

#include "core/app/links/heartbeat.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/predefined_messages.hpp"

namespace rescue::app {
namespace {

using protocol::MessageType;
using protocol::Outcome;
using protocol::RefusalReason;

RefusalReason reason_of(CommandRefusal refusal) noexcept {
  switch (refusal) {
    case CommandRefusal::none: return RefusalReason::none;
    case CommandRefusal::state_machine: return RefusalReason::state_machine;
    case CommandRefusal::unreachable: return RefusalReason::unreachable_joint;
    case CommandRefusal::bad_mode: return RefusalReason::bad_request;
    case CommandRefusal::clear_refused: return RefusalReason::clear_refused;
  }
  return RefusalReason::busy;
}

// A joint already where the request would take it (issue 36 item 7): it is left as it is and the
// request succeeds for it, so a command repeated, or given to the whole robot after one joint was
// handled, changes nothing twice. enable: Enabled; disable: its drive already off (any state but
// Enabled); initialize: Enabled in its default mode; select_mode: that mode chosen (Configured, Ready
// or Enabled).
bool already_there(const ControlRequest& r, const PublishedJointStatus& s, std::size_t j) noexcept {
  switch (r.type) {
    case MessageType::enable: return s.state == fsm::JointState::enabled;
    case MessageType::disable: return s.state != fsm::JointState::enabled;
    case MessageType::initialize: return s.state == fsm::JointState::enabled && s.mode == kJoints[j].default_mode;
    case MessageType::select_mode:
      return s.mode == r.mode && s.state != fsm::JointState::idle && s.state != fsm::JointState::error;
    default: return false;
  }
}

// "Enabled", "disabled", "initialized", "in that mode": what the unchanged joints already are.
const char* already_what(MessageType type) noexcept {
  switch (type) {
    case MessageType::enable: return "Enabled";
    case MessageType::disable: return "disabled";
    case MessageType::initialize: return "initialized";
    default: return "in that mode";
  }
}

// The reply's text for joints left unchanged: their names when they fit, else how many (the reply's
// joint mask names them all).
void unchanged_text(MessageType type, JointMask unchanged, char* text, std::size_t size) noexcept {
  char names[kJointNamesCapacity];
  format_joint_names(unchanged, names, sizeof names);
  if (std::strlen(names) <= 30) {
    (void)std::snprintf(text, size, "already %s, unchanged: %s", already_what(type), names);
  } else {
    (void)std::snprintf(text, size, "already %s, unchanged: %u joints", already_what(type),
                        static_cast<unsigned>(std::bitset<32>(unchanged).count()));
  }
}

JointCommandSequence steps_of(const ControlRequest& r, JointMask joints) noexcept {
  JointCommandSequence s;
  switch (r.type) {
    case MessageType::initialize: return initialize_robot_commands(joints);
    case MessageType::enable: (void)s.push_back(JointCommand{joints, fsm::JointInput::enable, ControlMode::none}); break;
    case MessageType::disable: return stop_robot_commands(joints);
    case MessageType::select_mode: (void)s.push_back(JointCommand{joints, fsm::JointInput::select_mode, r.mode}); break;
    case MessageType::clear_joints: return clear_repaired_joints_commands(joints, false);
    case MessageType::clear_moved: return clear_repaired_joints_commands(joints, true);
    case MessageType::hold:
      (void)s.push_back(JointCommand{joints, fsm::JointInput::disable, ControlMode::none});
      (void)s.push_back(JointCommand{joints, fsm::JointInput::set_reference, ControlMode::none});
      (void)s.push_back(JointCommand{joints, fsm::JointInput::enable, ControlMode::none});
      break;
    default: break;
  }
  return s;
}

}  // namespace

void MessageParser::reply(const ControlRequest& request, Outcome outcome, RefusalReason reason, JointMask refused,
                          const char* text, const std::array<JointRefusalNote, kJointCount>* notes) noexcept {
  ControlReply r;
  r.reply_address = request.reply_address;
  r.reply_port = request.reply_port;
  r.sender = request.sender;
  r.request_sequence = request.sequence;
  r.request_type = request.type;
  r.outcome = outcome;
  r.reason = reason;
  r.refused_joints = refused;
  protocol::set_text(r.text, text);
  for (std::size_t j = 0; notes != nullptr && j < kJointCount; ++j) {
    if ((refused & joint_bit(j)) == 0) continue;
    r.joint_refusals[j].why = (*notes)[j].why;
    r.joint_refusals[j].state = static_cast<std::uint8_t>((*notes)[j].state);
    r.joint_refusals[j].input = static_cast<std::uint8_t>((*notes)[j].input);
  }
  MessageSink<ControlReply>* sink = request.reply_address == 0 && request.reply_port == 0 ? ports_.local_replies
                                                                                          : ports_.network_replies;
  if (sink == nullptr || !sink->try_send(r)) ++replies_dropped_;
}

void MessageParser::start_rc_input(const ControlRequest& request) noexcept {
  const std::uint8_t task = request.task;
  char text[protocol::kReplyTextSize];
  const std::int64_t beat =
      ports_.rc_heartbeat_ns != nullptr && task < protocol::kMaxRcTasks ? (*ports_.rc_heartbeat_ns)[task].load(std::memory_order_acquire) : 0;
  // Heartbeats are monotonic-clock times; the parser's `now` is too (one clock per machine). A
  // damaged beat (links/heartbeat.hpp) tells nothing of the task: not running, counted.
  const HeartbeatAge judged = heartbeat_age(now_, beat);
  if (judged.kind == HeartbeatAge::Kind::damaged) ++damaged_beats_;
  if (judged.kind != HeartbeatAge::Kind::whole || judged.age > kRcTaskSilence || ports_.rc_inputs[task] == nullptr) {
    (void)std::snprintf(text, sizeof text, "no RC task running (RC task %u)", static_cast<unsigned>(task));
    reply(request, Outcome::refused, RefusalReason::no_rc_task, 0, text);
    return;
  }
  if (request.type != MessageType::take_owner && ports_.owner != nullptr) {
    const std::uint8_t holder = ports_.owner->task();
    const bool being_taken = taking_task_ == task && now_ - taking_since_ <= kRcTaskSilence;
    if (holder != task && !being_taken) {
      char owner[16] = "none";
      if (holder != kNoOwnerTask) (void)std::snprintf(owner, sizeof owner, "rc%u", static_cast<unsigned>(holder));
      (void)std::snprintf(text, sizeof text, "not owner (owner: %s)", owner);
      reply(request, Outcome::refused, RefusalReason::not_owner, 0, text);
      return;
    }
  }
  RcTaskInput input = request.rc;  // as the socket handler converted it
  input.kind = request.type == MessageType::move_effector ? RcInputKind::end_effector_target
               : request.type == MessageType::hand        ? RcInputKind::hand
                                                          : RcInputKind::take_ownership;
  input.sequence = request.sequence;
  if (!ports_.rc_inputs[task]->try_send(input)) {
    (void)std::snprintf(text, sizeof text, "RC task %u input queue full", static_cast<unsigned>(task));
    reply(request, Outcome::refused, RefusalReason::busy, 0, text);
    return;
  }
  if (request.type == MessageType::take_owner) {
    taking_task_ = task;
    taking_since_ = now_;
  }
  (void)std::snprintf(text, sizeof text, "queued to RC task %u", static_cast<unsigned>(task));
  reply(request, Outcome::accepted, RefusalReason::none, 0, text);
}

void MessageParser::start(const ControlRequest& request, hal::Nanoseconds now) noexcept {
  ++requests_;
  if (request.type == MessageType::move_effector || request.type == MessageType::hand ||
      request.type == MessageType::take_owner) {
    start_rc_input(request);
    return;
  }
  JointMask joints = request.joints & kAllJoints;
  JointMask skipped = 0;
  RobotSample sample{};
  RobotJointStatus status{};
  const bool have_sample = ports_.samples != nullptr && ports_.samples->try_read(sample);
  const bool have_status = ports_.joint_status != nullptr && ports_.joint_status->try_read(status);
  JointMask unchanged = 0;
  for (std::size_t j = 0; have_status && j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) != 0 && already_there(request, status[j], j)) unchanged |= joint_bit(j);
  }
  joints &= ~unchanged;
  if (joints == 0 && unchanged != 0) {
    char text[protocol::kReplyTextSize];
    unchanged_text(request.type, unchanged, text, sizeof text);
    reply(request, Outcome::accepted, RefusalReason::none, unchanged, text);
    return;
  }
  if (request.type == MessageType::initialize) {
    // "for every reachable joint": the others are named in the reply, not refused.
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((joints & joint_bit(j)) == 0) continue;
      if (!have_sample || !sample[j].reachable || (have_status && status[j].lost)) skipped |= joint_bit(j);
    }
    joints &= ~skipped;
    if (joints == 0) {
      reply(request, Outcome::refused, RefusalReason::unreachable_joint, skipped, "no selected joint is reachable");
      return;
    }
  } else if (request.type == MessageType::hold) {
    JointMask enabled = 0;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if (have_status && status[j].state == fsm::JointState::enabled) enabled |= joint_bit(j);
    }
    skipped = joints & ~enabled;
    joints &= enabled;
    if (joints == 0) {
      reply(request, Outcome::refused, RefusalReason::state_machine, skipped, "no selected joint is Enabled");
      return;
    }
  }
  const JointCommandSequence steps = steps_of(request, joints);
  if (steps.empty()) {
    reply(request, Outcome::refused, RefusalReason::bad_request, 0, "not a joint command");
    return;
  }
  pending_ = Pending{};
  pending_.active = true;
  pending_.request = request;
  pending_.id = next_id_++;
  if (next_id_ == 0) next_id_ = 1;
  const bool clear = steps[0].kind == JointCommandKind::clear_lost || steps[0].kind == JointCommandKind::clear_lost_moved;
  pending_.deadline = now + (clear ? kClearReplyTimeout : kReplyTimeout);
  pending_.skipped = skipped;
  pending_.unchanged = unchanged;
  const bool local = request.reply_address == 0 && request.reply_port == 0;
  std::uint8_t index = 0;
  for (JointCommand command : steps) {
    command.request = pending_.id;
    command.all_or_nothing = !local;
    command.step = index++;
    command.steps = static_cast<std::uint8_t>(steps.size());
    if (!ports_.joint_commands->try_send(command)) break;  // the reply times out as busy
    ++pending_.steps;
  }
}

void MessageParser::finish() noexcept {
  const ControlRequest& request = pending_.request;
  char text[protocol::kReplyTextSize];
  char names[kJointNamesCapacity];
  if (pending_.refused != 0) {
    const JointCommandOutcome& f = pending_.first_refusal;
    const std::size_t j = f.first_joint < kJointCount ? f.first_joint : 0;
    const JointRefusalNote& note = pending_.notes[j];
    std::size_t others = 0;
    for (std::size_t k = 0; k < kJointCount; ++k) others += k != j && (pending_.refused & joint_bit(k)) != 0 ? 1U : 0U;
    char more[16] = "";
    if (others != 0) (void)std::snprintf(more, sizeof more, " (+%u more)", static_cast<unsigned>(others % 100U));
    if (note.why == protocol::JointRefusal::state_machine) {
      (void)std::snprintf(text, sizeof text, "%.18s: %.16s in %.10s%.12s", kJoints[j].name, fsm::to_string(note.input),
                          fsm::to_string(note.state), more);
    } else {
      (void)std::snprintf(text, sizeof text, "%.18s: %.30s%.12s", kJoints[j].name, protocol::to_string(note.why), more);
    }
    reply(request, Outcome::refused, reason_of(f.first_reason), pending_.refused, text, &pending_.notes);
  } else if (pending_.outcomes < pending_.steps || pending_.steps == 0) {
    reply(request, Outcome::refused, RefusalReason::busy, 0, "the joint manager did not answer in time");
  } else if (pending_.skipped != 0) {
    format_joint_names(pending_.skipped, names, sizeof names);
    // initialize leaves out the unreachable joints, hold the ones that are not Enabled.
    (void)std::snprintf(text, sizeof text, "%s, left out: %.37s",
                        request.type == MessageType::hold ? "not Enabled" : "not reachable", names);
    reply(request, Outcome::accepted, RefusalReason::none, pending_.skipped, text);
  } else if (pending_.unchanged != 0) {
    unchanged_text(request.type, pending_.unchanged, text, sizeof text);
    reply(request, Outcome::accepted, RefusalReason::none, pending_.unchanged, text);
  } else {
    reply(request, Outcome::accepted, RefusalReason::none, 0, "");
  }
  pending_.active = false;
}

void MessageParser::step(hal::Nanoseconds now) noexcept {
  now_ = now;
  JointCommandOutcome outcome;
  while (ports_.outcomes != nullptr && ports_.outcomes->try_receive(outcome)) {
    if (!pending_.active || outcome.request != pending_.id) continue;  // a late answer to a timed-out request
    ++pending_.outcomes;
    pending_.applied |= outcome.applied;
    if (outcome.refused != 0 && pending_.refused == 0) pending_.first_refusal = outcome;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((outcome.refused & ~pending_.refused & joint_bit(j)) != 0) pending_.notes[j] = outcome.notes[j];
    }
    pending_.refused |= outcome.refused;
  }
  if (pending_.active && (pending_.outcomes >= pending_.steps || now >= pending_.deadline)) finish();
  for (std::size_t n = 0; n < kMaxRequestsPerStep && !pending_.active; ++n) {
    ControlRequest request;
    // The operator on this machine first (start-up initialize, clears, the disable at exit), then the network.
    const bool local = ports_.local != nullptr && ports_.local->try_receive(request);
    if (!local && !(ports_.network != nullptr && ports_.network->try_receive(request))) break;
    start(request, now);
  }
}

}  // namespace rescue::app
