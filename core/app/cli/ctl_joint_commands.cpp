// ctl's commands (docs/operator.md "Commands"): the joint verbs of the joint state machine (init,
// enable, disable, hold, clear), mode, move and hand to an RC task, and owner (which RC task owns the
// motion, or one takes it). Each verb's request, and the robot's reply printed with every blocking
// joint's own reason (all or nothing: a refused command changed no joint).
#include "core/app/cli/ctl_joint_commands.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/app/cli/ctl_output.hpp"
#include "core/app/cli/ctl_robot_queries.hpp"
#include "core/robot/robot.hpp"
#include "fsm/machines/joint_status_dfa.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

char g_text[1024];  // the error text naming what the user typed (one client process)

// JOINTS that do not parse: the error names the item and lists the valid names.
Error bad_joint_names(const char* list, const Error& error, bool all_allowed) noexcept {
  char names[kJointNamesCapacity];
  format_joint_names(kAllJoints, names, sizeof names);
  char item[40] = "";
  // The item the parser stopped at (error.detail0: 1-based), as typed.
  const char* begin = list;
  for (std::uint32_t i = 1; begin != nullptr && i < error.detail0; ++i) {
    begin = std::strchr(begin, ',');
    if (begin != nullptr) ++begin;
  }
  if (begin != nullptr) {
    std::size_t n = 0;
    while (begin[n] != '\0' && begin[n] != ',' && n + 1 < sizeof item) {
      item[n] = begin[n];
      ++n;
    }
    item[n] = '\0';
  }
  (void)std::snprintf(g_text, sizeof g_text, "%s: '%s' (in '%s'); the joints: %s%s", error.what, item, list, names,
                      all_allowed ? " (or all)" : "");
  return make_error(Errc::invalid_argument, g_text, error.detail0);
}

Result<JointMask> joints_argument(const ParsedArgs& args, std::size_t index) noexcept {
  if (args.positional_count() <= index || std::strcmp(args.positional(index), "all") == 0) return kAllJoints;
  Result<JointMask> joints = parse_joint_names(args.positional(index));
  if (!joints.ok()) return bad_joint_names(args.positional(index), joints.error(), true);
  return joints;
}

// --task N: the RC task move and hand go to.
Result<std::uint8_t> task_option(const ParsedArgs& args) noexcept {
  const Result<std::int64_t> task = args.integer("task", 0, 0, static_cast<std::int64_t>(protocol::kMaxRcTasks) - 1);
  if (!task.ok()) return make_error(Errc::invalid_argument, "--task must be 0..3");
  return static_cast<std::uint8_t>(task.value());
}

// EFFECTOR (move) or the hand (hand): left or right.
Result<protocol::Effector> side_of(const char* text, const char* error) noexcept {
  if (std::strcmp(text, "left") == 0) return protocol::Effector::left_hand;
  if (std::strcmp(text, "right") == 0) return protocol::Effector::right_hand;
  return make_error(Errc::invalid_argument, error);
}

// The joint verbs: the message each sends, all joints when JOINTS is not given.
struct JointVerb {
  const char* verb;
  MessageType type;
};
constexpr JointVerb kJointVerbs[] = {{"init", MessageType::initialize}, {"enable", MessageType::enable},
                                     {"disable", MessageType::disable}, {"hold", MessageType::hold},
                                     {"clear", MessageType::clear_joints}};

// One blocking joint's detail, as the reply gives it ("enable in Idle", "still unreachable: ...").
void joint_refusal_detail(const protocol::JointRefusalRecord& jr, char* out, std::size_t capacity) noexcept {
  if (jr.why == protocol::JointRefusal::state_machine) {
    (void)std::snprintf(out, capacity, "%s in %s", fsm::to_string(static_cast<fsm::JointInput>(jr.input)),
                        fsm::to_string(static_cast<fsm::JointState>(jr.state)));
  } else if (jr.why == protocol::JointRefusal::unreachable) {
    (void)std::snprintf(out, capacity, "does not answer (only disable and reset are taken)");
  } else {
    (void)std::snprintf(out, capacity, "%s", protocol::to_string(jr.why));
  }
}

bool has_joint_refusals(const protocol::ReplyPayload& r) noexcept {
  return std::any_of(r.joint_refusals.begin(), r.joint_refusals.end(),
                     [](const protocol::JointRefusalRecord& jr) noexcept { return jr.why != protocol::JointRefusal::none; });
}

int print_reply(const char* verb, const Message& m, bool json) noexcept {
  const protocol::ReplyPayload& r = m.reply;
  const bool accepted = r.outcome == protocol::Outcome::accepted;
  char detail[96];
  if (json) {
    begin_json(accepted);
    (void)std::printf(R"(,"accepted":%s,"reason":"%s","joints":[)", accepted ? "true" : "false", protocol::to_string(r.reason));
    bool listed = false;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((r.refused_joints & joint_bit(j)) == 0) continue;
      (void)std::printf("%s\"%s\"", listed ? "," : "", kJoints[j].name);
      listed = true;
    }
    (void)std::printf(R"(],"detail":)");
    print_json_string(r.text.data());
    if (!accepted) {
      // Every blocking joint with its own reason (all or nothing: none of them changed).
      (void)std::printf(",\"refused\":[");
      bool first = true;
      for (std::size_t j = 0; j < kJointCount; ++j) {
        const protocol::JointRefusalRecord& jr = r.joint_refusals[j];
        if (jr.why == protocol::JointRefusal::none) continue;
        joint_refusal_detail(jr, detail, sizeof detail);
        (void)std::printf(R"(%s{"joint":"%s","reason":"%s","state":"%s","detail":"%s"})",
                          first ? "" : ",", kJoints[j].name, protocol::to_string(protocol::reason_of(jr.why)),
                          fsm::to_string(static_cast<fsm::JointState>(jr.state)), detail);
        first = false;
      }
      (void)std::printf("]");
    }
    end_json();
  } else if (!accepted && has_joint_refusals(r)) {
    // One line per blocking joint, each with its own reason.
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const protocol::JointRefusalRecord& jr = r.joint_refusals[j];
      if (jr.why == protocol::JointRefusal::none) continue;
      joint_refusal_detail(jr, detail, sizeof detail);
      (void)std::printf("%s: refused: %s: %s: %s\n", verb, protocol::to_string(protocol::reason_of(jr.why)),
                        kJoints[j].name, detail);
    }
  } else if (accepted) {
    if (r.text[0] != '\0') {
      (void)std::printf("%s: accepted (", verb);
      print_text_string(r.text.data());
      (void)std::printf(")\n");
    } else {
      (void)std::printf("%s: accepted\n", verb);
    }
  } else {
    (void)std::printf("%s: refused: %s: ", verb, protocol::to_string(r.reason));
    print_text_string(r.text.data());
    (void)std::printf("\n");
  }
  return accepted ? 0 : static_cast<int>(CtlExit::refused);
}

}  // namespace

Result<Message> build_joint_command(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  const char* verb = args.positional(0);
  const JointVerb* v = std::find_if(std::begin(kJointVerbs), std::end(kJointVerbs),
                                    [verb](const JointVerb& j) { return std::strcmp(j.verb, verb) == 0; });
  if (v == std::end(kJointVerbs)) return make_error(Errc::invalid_argument, "not a joint verb");
  const Result<JointMask> joints = joints_argument(args, 1);
  if (!joints.ok()) return joints.error();
  Message m;
  m.header.type = v->type;
  if (args.has("moved")) m.header.type = MessageType::clear_moved;  // --moved only reaches clear (kCtlVerbOptions)
  m.joints.joints = joints.value();
  return m;
}

Result<Message> build_mode(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  Message m;
  const Result<JointMask> joints = parse_joint_names(args.positional(1));
  if (!joints.ok()) return bad_joint_names(args.positional(1), joints.error(), false);
  const char* mode = args.positional(2);
  m.header.type = MessageType::select_mode;
  m.joints.joints = joints.value();
  if (std::strcmp(mode, "csp") == 0) m.joints.mode = ControlMode::cyclic_position;
  else if (std::strcmp(mode, "csv") == 0) m.joints.mode = ControlMode::cyclic_velocity;
  else if (std::strcmp(mode, "cst") == 0) m.joints.mode = ControlMode::cyclic_torque;
  else return make_error(Errc::invalid_argument, "MODE must be csp, csv or cst");
  return m;
}

Result<Message> build_move(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  const Result<std::uint8_t> task = task_option(args);
  if (!task.ok()) return task.error();
  const Result<protocol::Effector> effector = side_of(args.positional(1), "EFFECTOR must be left or right");
  if (!effector.ok()) return effector.error();
  Message m;
  m.header.type = MessageType::move_effector;
  m.move.task = task.value();
  m.move.effector = effector.value();
  double v[6] = {};
  const char* at = args.positional(2);
  for (std::size_t i = 0; i < 6; ++i) {  // six decimal numbers separated by commas, nothing else
    char* end = nullptr;
    errno = 0;
    v[i] = std::strtod(at, &end);
    const char expected = i < 5 ? ',' : '\0';
    if (end == at || errno != 0 || *end != expected) {
      return make_error(Errc::invalid_argument, "POSE must be x,y,z,roll,pitch,yaw");
    }
    at = end + 1;
  }
  for (std::size_t i = 0; i < 3; ++i) {
    m.move.position_m[i] = v[i];
    m.move.rpy_rad[i] = v[i + 3];
  }
  return m;
}

Result<Message> build_hand(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  const Result<std::uint8_t> task = task_option(args);
  if (!task.ok()) return task.error();
  const Result<protocol::Effector> hand = side_of(args.positional(1), "hand: left or right");
  if (!hand.ok()) return hand.error();
  Message m;
  m.header.type = MessageType::hand;
  m.hand.task = task.value();
  m.hand.hand = hand.value();
  if (std::strcmp(args.positional(2), "open") == 0) m.hand.action = protocol::HandAction::open;
  else if (std::strcmp(args.positional(2), "close") == 0) m.hand.action = protocol::HandAction::close;
  else return make_error(Errc::invalid_argument, "hand: open or close");
  return m;
}

Result<Message> build_owner(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  Message m;
  if (args.positional_count() == 1) {  // who owns the motion (like list_controllers)
    m.header.type = MessageType::get_owner;
    return m;
  }
  char* end = nullptr;
  const long t = std::strtol(args.positional(1), &end, 10);
  if (end == args.positional(1) || *end != '\0' || t < 0 || t >= static_cast<long>(protocol::kMaxRcTasks)) {
    return make_error(Errc::invalid_argument, "owner TASK: 0..3");
  }
  m.header.type = MessageType::take_owner;
  m.owner.task = static_cast<std::uint8_t>(t);
  return m;
}

int print_command_reply(const Message& /*request*/, const Message& answer) noexcept {
  if (answer.header.type != MessageType::reply) return ctl_unexpected_answer(answer);
  return print_reply(ctl_output().verb, answer, ctl_output().json);
}

int print_owner_answer(const Message& request, const Message& answer) noexcept {
  if (request.header.type == MessageType::get_owner && answer.header.type == MessageType::owner_state) {
    print_owner(answer, ctl_output().json);
    return 0;
  }
  return print_command_reply(request, answer);
}

}  // namespace rescue::app
