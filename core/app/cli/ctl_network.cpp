#include "core/app/cli/ctl_network.hpp"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/master/slave_recovery.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

constexpr std::size_t kPlanned = drivers::kRobotNetworkPlan.size();

const char* slave_name(std::size_t position) noexcept {
  return drivers::slave_end_name(static_cast<std::uint8_t>(position));
}

const char* recovery_name(std::uint8_t recovery) noexcept {
  return recovery < protocol::kRecoveryStates ? ecat::to_string(static_cast<ecat::RecoveryState>(recovery)) : "?";
}

// The state a graph shows for a slave: its service, and its recovery when one runs.
void graph_state(const protocol::GraphRecord& g, char* out, std::size_t size) noexcept {
  if ((g.flags & protocol::kSlaveInExchange) != 0) {
    (void)std::snprintf(out, size, "%s", al_state_name(g.al_state));
  } else if (g.recovery != 0) {
    (void)std::snprintf(out, size, "%s, recovering: %s", slave_service_name(g.flags), recovery_name(g.recovery));
  } else {
    (void)std::snprintf(out, size, "%s", slave_service_name(g.flags));
  }
}

// The slave (position) SLAVE names: a slave's name or its position.
Result<std::uint32_t> slave_argument(const char* text) noexcept {
  for (std::size_t p = 0; p < kPlanned; ++p) {
    if (std::strcmp(text, slave_name(p)) == 0) return std::uint32_t{1} << p;
  }
  char* end = nullptr;
  const long p = std::strtol(text, &end, 10);
  if (end != text && *end == '\0' && p >= 0 && p < static_cast<long>(kPlanned)) return std::uint32_t{1} << p;
  return make_error(Errc::invalid_argument, "diag --reset SLAVE: a slave's name (ctl slaves) or its position 0..22");
}

// Joints behind the cable into `position`: it and every slave downstream of it (the graph's tree).
JointMask joints_behind(const protocol::GraphPayload& g, std::size_t position) noexcept {
  std::uint32_t below = std::uint32_t{1} << position;
  JointMask joints = 0;
  for (std::size_t p = 0; p < g.count; ++p) {  // upstream always comes earlier in frame order
    const protocol::GraphRecord& r = g.slaves[p];
    if (p != position && (r.upstream == protocol::kGraphNone || r.upstream >= p || (below & (std::uint32_t{1} << r.upstream)) == 0)) continue;
    below |= std::uint32_t{1} << p;
    if (r.joint != protocol::kGraphNone) joints |= joint_bit(r.joint);
  }
  return joints;
}

// The slave cabled to `parent`'s `port` (kGraphNone: master's own port 0 when parent is kGraphNone).
std::uint8_t child_on(const protocol::GraphPayload& g, std::uint8_t parent, std::uint8_t port) noexcept {
  for (std::size_t p = 0; p < g.count; ++p) {
    if (g.slaves[p].upstream == parent && (parent == protocol::kGraphNone || g.slaves[p].upstream_port == port)) {
      return static_cast<std::uint8_t>(p);
    }
  }
  return protocol::kGraphNone;
}

// The chain from `first`: each slave and the one cabled to its port 1, while they are joint drives.
void print_chain(const protocol::GraphPayload& g, std::uint8_t first) noexcept {
  char state[64];
  for (std::uint8_t p = first; p != protocol::kGraphNone;) {
    graph_state(g.slaves[p], state, sizeof state);
    (void)std::printf("%s%s [%s]", p == first ? "" : " -> ", slave_name(p), state);
    if (g.slaves[p].kind == 0) break;  // a junction has a line of its own
    p = child_on(g, p, 1);
  }
  (void)std::printf("\n");
}

void print_graph_text(const protocol::GraphPayload& g) noexcept {
  (void)std::printf("chains (port of the junction -> slaves along the cable, [state]):\n");
  const std::uint8_t root = child_on(g, protocol::kGraphNone, 0);
  if (root != protocol::kGraphNone) {
    (void)std::printf("master port 0 -> ");
    print_chain(g, root);
  }
  for (std::size_t p = 0; p < g.count; ++p) {
    if (g.slaves[p].kind != 0) continue;  // chains start at the junctions' ports
    for (std::uint8_t port = 1; port < protocol::kDiagPorts; ++port) {
      const std::uint8_t c = child_on(g, static_cast<std::uint8_t>(p), port);
      if (c == protocol::kGraphNone) continue;
      (void)std::printf("%s port %u -> ", slave_name(p), static_cast<unsigned>(port));
      print_chain(g, c);
    }
  }
  (void)std::printf("cables (upstream:port -> slave: the joints behind it):\n");
  char names[kJointNamesCapacity];
  for (std::size_t p = 0; p < g.count; ++p) {
    const protocol::GraphRecord& r = g.slaves[p];
    format_joint_names(joints_behind(g, p), names, sizeof names);
    (void)std::printf("  %s:%u -> %s: %s\n", r.upstream == protocol::kGraphNone ? "master" : slave_name(r.upstream),
                      static_cast<unsigned>(r.upstream_port), slave_name(p), names);
  }
}

void print_graph_dot(const protocol::GraphPayload& g) noexcept {
  (void)std::printf("digraph robot {\n  rankdir=LR;\n  node [shape=box, fontname=\"Helvetica\"];\n");
  (void)std::printf("  master [label=\"master\", shape=doubleoctagon];\n");
  char state[64];
  for (std::size_t p = 0; p < g.count; ++p) {
    const protocol::GraphRecord& r = g.slaves[p];
    graph_state(r, state, sizeof state);
    const bool in = (r.flags & protocol::kSlaveInExchange) != 0;
    const char* color = in ? "black" : (r.flags & protocol::kSlaveLost) != 0 ? "red" : "orange";
    (void)std::printf("  s%zu [label=\"%s\\n#%zu 0x%04x\\n%s\", shape=%s, color=%s];\n", p, slave_name(p), p,
                      static_cast<unsigned>(r.station), state, r.kind == 0 ? "box3d" : "box", color);
  }
  for (std::size_t p = 0; p < g.count; ++p) {
    const protocol::GraphRecord& r = g.slaves[p];
    char from[8] = "master";
    if (r.upstream != protocol::kGraphNone) (void)std::snprintf(from, sizeof from, "s%u", static_cast<unsigned>(r.upstream));
    (void)std::printf("  %s -> s%zu [taillabel=\"%u\", headlabel=\"0\"];\n", from, p, static_cast<unsigned>(r.upstream_port));
  }
  (void)std::printf("}\n");
}

void print_graph_json(const protocol::GraphPayload& g) noexcept {
  (void)std::printf("{\"age_ms\":%" PRIu32 ",\"stale\":%s,\"slaves\":[", g.age.age_ms, g.age.stale ? "true" : "false");
  for (std::size_t p = 0; p < g.count; ++p) {
    const protocol::GraphRecord& r = g.slaves[p];
    (void)std::printf(R"(%s{"position":%zu,"name":"%s","kind":"%s","station":%u,"upstream":)", p == 0 ? "" : ",", p,
                      slave_name(p), r.kind == 0 ? "junction" : "joint_drive", static_cast<unsigned>(r.station));
    if (r.upstream == protocol::kGraphNone) {
      (void)std::printf("\"master\"");
    } else {
      (void)std::printf("\"%s\"", slave_name(r.upstream));
    }
    (void)std::printf(R"(,"upstream_port":%u,"joint":)", static_cast<unsigned>(r.upstream_port));
    if (r.joint == protocol::kGraphNone) {
      (void)std::printf("null");
    } else {
      (void)std::printf("\"%s\"", kJoints[r.joint].name);
    }
    (void)std::printf(",\"branch\":");
    if (r.branch == protocol::kGraphNone) {
      (void)std::printf("null");
    } else {
      (void)std::printf("%u", static_cast<unsigned>(r.branch));
    }
    (void)std::printf(R"(,"al_state":"%s","service":"%s","recovery":"%s","joints_behind":[)", al_state_name(r.al_state),
                      slave_service_name(r.flags), recovery_name(r.recovery));
    const JointMask behind = joints_behind(g, p);
    bool first = true;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((behind & joint_bit(j)) == 0) continue;
      (void)std::printf("%s\"%s\"", first ? "" : ",", kJoints[j].name);
      first = false;
    }
    (void)std::printf("]}");
  }
  (void)std::printf("]}\n");
}

}  // namespace

const char* al_state_name(std::uint8_t s) noexcept {
  switch (s) {
    case 1: return "INIT";
    case 2: return "PREOP";
    case 3: return "BOOT";
    case 4: return "SAFEOP";
    case 8: return "OP";
    default: return "-";
  }
}

const char* slave_service_name(std::uint8_t flags) noexcept {
  return (flags & protocol::kSlaveLost) != 0            ? "lost"
         : (flags & protocol::kSlaveOutOfService) != 0  ? "out of service"
         : (flags & protocol::kSlaveInExchange) != 0    ? "in exchange"
                                                        : "not in exchange";
}

Result<Message> build_network_request(const char* verb, const ParsedArgs& args) noexcept {
  const bool slaves = std::strcmp(verb, "slaves") == 0;
  const bool graph = std::strcmp(verb, "graph") == 0;
  const bool diag = std::strcmp(verb, "diag") == 0;
  Message m;
  if (slaves && args.has("verbose")) {
    if (args.positional_count() != 1) return make_error(Errc::invalid_argument, "slaves [-v] takes no argument");
    m.header.type = MessageType::get_slave_info;
    return m;
  }
  if (graph) {
    const char* format = args.value("format");
    if (format != nullptr && std::strcmp(format, "text") != 0 && std::strcmp(format, "dot") != 0) {
      return make_error(Errc::invalid_argument, "graph --format: text or dot");
    }
    if (format != nullptr && std::strcmp(format, "dot") == 0 && args.has("json")) {
      return make_error(Errc::invalid_argument, "graph: --format dot or --json, not both");
    }
    if (args.positional_count() != 1) return make_error(Errc::invalid_argument, "graph takes no argument");
    m.header.type = MessageType::get_graph;
    return m;
  }
  if (diag && args.has("reset")) {
    m.header.type = MessageType::diag_reset;
    m.diag_reset.slaves = (std::uint32_t{1} << kPlanned) - 1;
    if (args.positional_count() > 2) return make_error(Errc::invalid_argument, "diag --reset [SLAVE]");
    if (args.positional_count() == 2) {
      const Result<std::uint32_t> one = slave_argument(args.positional(1));
      if (!one.ok()) return one.error();
      m.diag_reset.slaves = one.value();
    }
    return m;
  }
  if (diag && args.positional_count() != 1) return make_error(Errc::invalid_argument, "diag [--reset [SLAVE]]");
  return make_error(Errc::not_found, "not a network verb");
}

// Like IgH's `ethercat slaves -v`: per slave its SII identity (as the master read it at bring-up)
// and the AL status register and code it answered last.
int print_slave_info(const Message& m, bool json) noexcept {
  const protocol::SlaveInfoPayload& p = m.slave_info;
  if (json) {
    (void)std::printf("{\"age_ms\":%" PRIu32 ",\"stale\":%s,\"slaves\":[", p.age.age_ms, p.age.stale ? "true" : "false");
  } else {
    if (p.age.stale) {
      (void)std::printf("STALE: the EtherCAT handler has completed no period for %" PRIu32 " ms; these figures are that old\n",
                        p.age.age_ms);
    }
    if (p.count == 0) (void)std::printf("no slave information published yet (the EtherCAT handler publishes it once cycling)\n");
    (void)std::printf("%-3s %-7s %-16s %-10s %-10s %-10s %-10s %-7s %s\n", "POS", "STATION", "NAME", "VENDOR", "PRODUCT",
                      "REVISION", "SERIAL", "AL", "AL STATUS CODE");
  }
  for (std::size_t i = 0; i < p.count; ++i) {
    const protocol::SlaveInfoRecord& s = p.slaves[i];
    const bool identity = (s.flags & protocol::kSlaveInfoIdentity) != 0;
    const bool read = (s.flags & protocol::kSlaveInfoAlRead) != 0;
    const auto state = static_cast<std::uint8_t>(s.al_status & ecat::reg::kAlStateMask);
    const bool error = (s.al_status & ecat::reg::kAlErrorBit) != 0;
    const char* code_name = ecat::reg::explain_al_status_code(s.al_status_code);
    if (json) {
      (void)std::printf(R"(%s{"position":%u,"station":%u,"name":"%s","identity_read":%s,"vendor_id":%u,"product_code":%u,)"
                        R"("revision":%u,"serial_number":%u,"al_status_read":%s,"al_state":"%s","al_error":%s,)"
                        R"("al_status_code":%u,"al_status_code_name":"%s"})",
                        i == 0 ? "" : ",", static_cast<unsigned>(s.position), static_cast<unsigned>(s.station),
                        slave_name(s.position), identity ? "true" : "false", s.vendor_id, s.product_code, s.revision,
                        s.serial_number, read ? "true" : "false", read ? al_state_name(state) : "-", error ? "true" : "false",
                        static_cast<unsigned>(s.al_status_code), code_name);
      continue;
    }
    char al[16] = "-";
    if (read) (void)std::snprintf(al, sizeof al, "%s%s", al_state_name(state), error ? "+ERR" : "");
    char code[64] = "-";
    if (read) (void)std::snprintf(code, sizeof code, "0x%04x %s", static_cast<unsigned>(s.al_status_code), code_name);
    if (identity) {
      (void)std::printf("%-3u 0x%04x  %-16s 0x%08x 0x%08x 0x%08x 0x%08x %-7s %s\n", static_cast<unsigned>(s.position),
                        static_cast<unsigned>(s.station), slave_name(s.position), s.vendor_id, s.product_code, s.revision,
                        s.serial_number, al, code);
    } else {
      (void)std::printf("%-3u 0x%04x  %-16s %-10s %-10s %-10s %-10s %-7s %s\n", static_cast<unsigned>(s.position),
                        static_cast<unsigned>(s.station), slave_name(s.position), "-", "-", "-", "-", al, code);
    }
  }
  if (json) (void)std::printf("]}\n");
  return 0;
}

int print_graph(const Message& m, bool json, const char* format) noexcept {
  if (json) {
    print_graph_json(m.graph);
  } else if (format != nullptr && std::strcmp(format, "dot") == 0) {
    print_graph_dot(m.graph);
  } else {
    if (m.graph.age.stale) {
      (void)std::printf("STALE: the EtherCAT handler has completed no period for %" PRIu32 " ms; these figures are that old\n",
                        m.graph.age.age_ms);
    }
    print_graph_text(m.graph);
  }
  return 0;
}

int print_diag_reset_reply(const Message& request, const Message& m, bool json) noexcept {
  const protocol::ReplyPayload& r = m.reply;
  const bool accepted = r.outcome == protocol::Outcome::accepted;
  const std::uint32_t slaves = request.diag_reset.slaves;
  const bool all = slaves == (std::uint32_t{1} << kPlanned) - 1;
  const char* one = "";
  for (std::size_t p = 0; p < kPlanned && !all; ++p) {
    if ((slaves & (std::uint32_t{1} << p)) != 0) one = slave_name(p);
  }
  if (json) {
    (void)std::printf(R"({"command":"diag --reset","accepted":%s,"reason":"%s","slaves":)", accepted ? "true" : "false",
                      protocol::to_string(r.reason));
    if (all) {
      (void)std::printf("\"all\"");
    } else {
      (void)std::printf("\"%s\"", one);
    }
    (void)std::printf(",\"detail\":\"%s\"}\n", r.text.data());
  } else if (accepted) {
    (void)std::printf("diag --reset: %s: %s\n", all ? "all slaves" : one, r.text.data());
  } else {
    (void)std::printf("diag --reset: refused: %s: %s\n", protocol::to_string(r.reason), r.text.data());
  }
  return accepted ? 0 : 1;
}

}  // namespace rescue::app
