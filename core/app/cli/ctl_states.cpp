#include "core/app/cli/ctl_states.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <strings.h>

#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "core/robot/robot.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;
using protocol::StateOutcome;
using protocol::StatesStatus;

char g_text[200];  // a usage error's text (ctl is one verb per process)

// INIT, PREOP, SAFEOP or OP (any case) as its AL control value; 0 for anything else.
std::uint8_t state_named(const char* text) noexcept {
  constexpr std::uint8_t kValues[] = {1, 2, 4, 8};
  const auto* found = std::find_if(std::begin(kValues), std::end(kValues),
                                   [text](std::uint8_t v) { return strcasecmp(text, protocol::al_state_name(v)) == 0; });
  return found != std::end(kValues) ? *found : 0;
}

// SLAVES: "all" or names / positions separated by commas; 0 when an item is no slave (g_text says which).
std::uint32_t slaves_named(const char* list) noexcept {
  if (std::strcmp(list, "all") == 0) return (std::uint32_t{1} << kSlaveCount) - 1;
  std::uint32_t mask = 0;
  const char* begin = list;
  for (;;) {
    char item[40] = "";
    const std::size_t n = std::strcspn(begin, ",");  // this item's length, up to the comma or the end
    const bool too_long = n >= sizeof item;            // no slave's name is that long
    const std::size_t kept = too_long ? sizeof item - 1 : n;
    std::memcpy(item, begin, kept);
    item[kept] = '\0';
    const std::size_t position = planned_slave_named(item);
    if (position >= kSlaveCount || too_long) {
      (void)std::snprintf(g_text, sizeof g_text,
                          "states SLAVES: '%.40s' is not a slave; slaves' names (ctl slaves) or positions 0..%zu, "
                          "separated by commas, or all",
                          item, kSlaveCount - 1);
      return 0;
    }
    mask |= std::uint32_t{1} << position;
    if (begin[n] == '\0') return mask;
    begin += n + 1;
  }
}

const char* outcome_reason(StateOutcome o) noexcept {
  switch (o) {
    case StateOutcome::reached: return "reached";
    case StateOutcome::refused: return "refused by the slave (AL status code below)";
    case StateOutcome::timeout: return "not reached within 1.5 s";
    case StateOutcome::not_answered: return "did not answer (lost or cut off)";
  }
  return "?";
}

const char* status_reason(StatesStatus s) noexcept {
  switch (s) {
    case StatesStatus::ok: return "";
    case StatesStatus::in_service:
      return "joints of these slaves are in service: their AL state is the master's (ctl states is for slaves "
             "out of service); nothing was written";
    case StatesStatus::not_reached: return "a slave did not reach the state";
    case StatesStatus::busy: return "another states request is under way; try again";
    case StatesStatus::recovering: return "the master's online recovery is configuring one of them; try again";
    case StatesStatus::not_cycling: return "the master is not cycling in OP; nothing was written";
    case StatesStatus::no_answer: return "the EtherCAT handler did not answer within 1.8 s";
  }
  return "?";
}

void print_joint_list_json(std::uint32_t joints) noexcept {
  (void)std::printf("[");
  bool listed = false;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) == 0) continue;
    (void)std::printf("%s\"%s\"", listed ? "," : "", kJoints[j].name);
    listed = true;
  }
  (void)std::printf("]");
}

}  // namespace

Result<Message> build_states(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  const bool listed = args.positional_count() > 2;
  const char* state_text = args.positional(listed ? 2 : 1);
  const std::uint8_t state = state_named(state_text);
  if (state == 0) {
    (void)std::snprintf(g_text, sizeof g_text, "states STATE: '%.20s' is not INIT, PREOP, SAFEOP or OP", state_text);
    return make_error(Errc::invalid_argument, g_text);
  }
  const std::uint32_t slaves = listed ? slaves_named(args.positional(1)) : slaves_named("all");
  if (slaves == 0) return make_error(Errc::invalid_argument, g_text);
  Message m;
  m.header.type = MessageType::states;
  m.states.slaves = slaves;
  m.states.state = state;
  return m;
}

int print_states_result(const Message& request, const Message& answer) noexcept {
  if (answer.header.type != MessageType::states_result) return ctl_unexpected_answer(answer);
  const protocol::StatesResultPayload& r = answer.states_result;
  if (r.slaves != request.states.slaves || r.state != request.states.state) {
    return ctl_error(CtlExit::bad_answer, "states: an answer for another request");
  }
  const bool ok = r.status == StatesStatus::ok;
  const bool written = ok || r.status == StatesStatus::not_reached;
  if (ctl_output().json) {
    begin_json(ok);
    (void)std::printf(R"(,"state":"%s","status":"%s")", protocol::al_state_name(r.state), protocol::to_string(r.status));
    if (!ok) {
      (void)std::printf(R"(,"reason":)");
      print_json_string(status_reason(r.status));
    }
    (void)std::printf(R"(,"in_service":)");
    print_joint_list_json(r.in_service);
    (void)std::printf(R"(,"slaves":[)");
    bool first = true;
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if ((r.slaves & (std::uint32_t{1} << p)) == 0) continue;
      (void)std::printf(R"(%s{"slave":"%s","position":%zu)", first ? "" : ",", planned_slave_name(p), p);
      first = false;
      if (written) {
        const protocol::SlaveStateRecord& s = r.records[p];
        (void)std::printf(R"(,"outcome":"%s","al_status":"0x%04X","al_state":"%s","al_error":%s,"al_code":"0x%04X")",
                          protocol::to_string(s.outcome), static_cast<unsigned>(s.al_status),
                          protocol::al_state_name(static_cast<std::uint8_t>(s.al_status & 0x0FU)),
                          (s.al_status & 0x10U) != 0 ? "true" : "false", static_cast<unsigned>(s.al_code));
      }
      (void)std::printf("}");
    }
    (void)std::printf(R"(],"frames":%u)", static_cast<unsigned>(r.frames));
    end_json();
    return ok ? 0 : static_cast<int>(CtlExit::refused);
  }
  if (!written) {
    (void)std::printf("states: %s: refused: %s\n", protocol::al_state_name(r.state), status_reason(r.status));
    if (r.in_service != 0) {
      char names[kJointNamesCapacity];
      format_joint_names(r.in_service, names, sizeof names);
      (void)std::printf("states: joints in service: %s\n", names);
    }
    return static_cast<int>(CtlExit::refused);
  }
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if ((r.slaves & (std::uint32_t{1} << p)) == 0) continue;
    const protocol::SlaveStateRecord& s = r.records[p];
    (void)std::printf("%-16s %-6s %s", planned_slave_name(p), protocol::al_state_name(r.state), outcome_reason(s.outcome));
    if (s.outcome != StateOutcome::not_answered) {
      (void)std::printf(" (AL status 0x%04X: %s%s", static_cast<unsigned>(s.al_status),
                        protocol::al_state_name(static_cast<std::uint8_t>(s.al_status & 0x0FU)),
                        (s.al_status & 0x10U) != 0 ? " + error" : "");
      if ((s.al_status & 0x10U) != 0) {
        (void)std::printf(", code 0x%04X %s", static_cast<unsigned>(s.al_code),
                          ecat::reg::explain_al_status_code(s.al_code));
      }
      (void)std::printf(")");
    }
    (void)std::printf("\n");
  }
  if (!ok) (void)std::printf("states: refused: %s\n", status_reason(r.status));
  return ok ? 0 : static_cast<int>(CtlExit::refused);
}

}  // namespace rescue::app
