#include "core/app/cli/ctl_network.hpp"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/app/cli/ctl_output.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/master/slave_recovery.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

const char* slave_name(std::size_t position) noexcept { return planned_slave_name(position); }

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

const char* ring_state_name(std::uint8_t state) noexcept {
  switch (state) {
    case protocol::kRingStateClosed: return "closed";
    case protocol::kRingStateOpen: return "open";
    case protocol::kRingStateLost: return "lost";
    default: return "none";
  }
}

bool ring_broken(const protocol::GraphPayload& g) noexcept {
  return g.ring.state == protocol::kRingStateOpen || g.ring.state == protocol::kRingStateLost;
}

// Whether the master places a break on the cable into `position` (the ring watch's place: right after
// the last slave the main port reaches, right before the first the ring port reaches).
bool cable_broken(const protocol::GraphPayload& g, std::size_t position) noexcept {
  if (!ring_broken(g)) return false;
  const std::uint8_t before = g.ring.before;
  const bool after_main_side = before == protocol::kRingMainPort ? position == 0 : before + 1U == position;
  return after_main_side || g.ring.after == position;
}
bool ring_cable_broken(const protocol::GraphPayload& g) noexcept {
  return ring_broken(g) && g.ring.after == protocol::kRingRingPort;
}

// "r_elbow (position 5)", "the master's main port".
void ring_place(std::uint8_t where, char* out, std::size_t size) noexcept {
  if (where == protocol::kRingMainPort) {
    (void)std::snprintf(out, size, "the master's main port");
  } else if (where == protocol::kRingRingPort) {
    (void)std::snprintf(out, size, "the master's ring port");
  } else {
    (void)std::snprintf(out, size, "%s (position %u)", slave_name(where), static_cast<unsigned>(where));
  }
}

// The ring's state in one line: "ring: open between X and Y; breaks 1, repairs 0, transients 0".
void print_ring_text(const protocol::GraphPayload& g) noexcept {
  const protocol::GraphRing& r = g.ring;
  (void)std::printf("ring return: %s port %u %s master ring port\n", slave_name(r.return_slave),
                    static_cast<unsigned>(r.return_port), ring_cable_broken(g) ? "-X-" : "->");
  char before[48];
  char after[48];
  ring_place(r.before, before, sizeof before);
  ring_place(r.after, after, sizeof after);
  if (r.state == protocol::kRingStateOpen) {
    (void)std::printf("ring: open between %s and %s", before, after);
  } else if (r.state == protocol::kRingStateLost) {
    const unsigned from = r.before == protocol::kRingMainPort ? 0U : r.before + 1U;
    const unsigned to = r.after == protocol::kRingRingPort ? static_cast<unsigned>(g.count) : r.after;
    (void)std::printf("ring: lost: %u slaves reachable from neither port, after %s and before %s", to > from ? to - from : 0U,
                      before, after);
  } else {
    (void)std::printf("ring: %s", ring_state_name(r.state));
  }
  (void)std::printf("; breaks %u, repairs %u, transients %u\n", static_cast<unsigned>(r.breaks),
                    static_cast<unsigned>(r.repairs), static_cast<unsigned>(r.transients));
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
    (void)std::printf("%s%s [%s]", p == first ? "" : (cable_broken(g, p) ? " -X- " : " -> "), slave_name(p), state);
    if (g.slaves[p].kind == 0) break;  // a junction has a line of its own
    p = child_on(g, p, 1);
  }
  (void)std::printf("\n");
}

void print_graph_text(const protocol::GraphPayload& g) noexcept {
  (void)std::printf("chains (port of the junction -> slaves along the cable, [state]):\n");
  const std::uint8_t root = child_on(g, protocol::kGraphNone, 0);
  if (root != protocol::kGraphNone) {
    (void)std::printf("master port 0 %s ", cable_broken(g, root) ? "-X-" : "->");
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
    (void)std::printf("  %s:%u -> %s: %s%s\n", r.upstream == protocol::kGraphNone ? "master" : slave_name(r.upstream),
                      static_cast<unsigned>(r.upstream_port), slave_name(p), names, cable_broken(g, p) ? " (broken)" : "");
  }
  if (g.ring.state != protocol::kRingStateNone) print_ring_text(g);
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
    (void)std::printf("  %s -> s%zu [taillabel=\"%u\", headlabel=\"0\"%s];\n", from, p, static_cast<unsigned>(r.upstream_port),
                      cable_broken(g, p) ? ", color=red, style=dashed, label=\"break\"" : "");
  }
  if (g.ring.state != protocol::kRingStateNone) {  // the ring-return cable, back to the master's second port
    (void)std::printf("  s%u -> master [taillabel=\"%u\", headlabel=\"ring\", style=bold%s];\n",
                      static_cast<unsigned>(g.ring.return_slave), static_cast<unsigned>(g.ring.return_port),
                      ring_cable_broken(g) ? ", color=red, label=\"break\"" : "");
  }
  (void)std::printf("}\n");
}

// "ring": null on a tree; else the state, the place of the break, the ring-return cable, the cables
// broken (named by the slave they lead into, "ring" for the ring-return cable) and the counts.
void print_ring_json(const protocol::GraphPayload& g) noexcept {
  const protocol::GraphRing& r = g.ring;
  if (r.state == protocol::kRingStateNone) {
    (void)std::printf(",\"ring\":null");
    return;
  }
  const auto place = [](std::uint8_t where) {
    if (where == protocol::kRingMainPort) return "master main port";
    if (where == protocol::kRingRingPort) return "master ring port";
    return slave_name(where);
  };
  const bool broken = ring_broken(g);
  (void)std::printf(R"(,"ring":{"state":"%s","before":)", ring_state_name(r.state));
  if (broken) {
    (void)std::printf(R"("%s","after":"%s")", place(r.before), place(r.after));
  } else {
    (void)std::printf(R"(null,"after":null)");
  }
  (void)std::printf(R"(,"return_from":"%s","return_port":%u,"broken_cables":[)", slave_name(r.return_slave),
                    static_cast<unsigned>(r.return_port));
  bool first = true;
  for (std::size_t p = 0; p < g.count; ++p) {
    if (!cable_broken(g, p)) continue;
    (void)std::printf("%s\"%s\"", first ? "" : ",", slave_name(p));
    first = false;
  }
  if (ring_cable_broken(g)) (void)std::printf("%s\"ring\"", first ? "" : ",");
  (void)std::printf(R"(],"breaks":%u,"repairs":%u,"transients":%u})", static_cast<unsigned>(r.breaks),
                    static_cast<unsigned>(r.repairs), static_cast<unsigned>(r.transients));
}

void print_graph_json(const protocol::GraphPayload& g) noexcept {
  begin_json(true);
  print_age_json(g.age);
  (void)std::printf(",\"slaves\":[");
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
  (void)std::printf("]");
  print_ring_json(g);
  end_json();
}

// Like IgH's `ethercat slaves -v`: per slave its SII identity (as the master read it at bring-up)
// and the AL status register and code it answered last.
void print_slave_info(const Message& m, bool json) noexcept {
  const protocol::SlaveInfoPayload& p = m.slave_info;
  if (json) {
    begin_json(true);
    print_age_json(p.age);
    (void)std::printf(",\"slaves\":[");
  } else {
    print_age_text(p.age);
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
  if (json) {
    (void)std::printf("]");
    end_json();
  }
}

void print_graph(const Message& m, bool json, const char* format) noexcept {
  if (json) {
    print_graph_json(m.graph);
  } else if (format != nullptr && std::strcmp(format, "dot") == 0) {
    print_graph_dot(m.graph);
  } else {
    print_age_text(m.graph.age);
    print_graph_text(m.graph);
  }
}

// ctl slaves: each slave's AL state, service and recovery (like IgH's `ethercat slaves`). The names
// are the robot's; the codec let only printable ASCII through (docs/protocol.md), so the table's
// columns hold.
void print_slaves(const Message& m, bool json) noexcept {
  if (json) {
    begin_json(true);
    print_age_json(m.slaves.age);
    (void)std::printf(",\"slaves\":[");
  }
  if (!json) {
    print_age_text(m.slaves.age);
    (void)std::printf("%-3s %-7s %-6s %-16s %-16s %-12s %s\n", "POS", "STATION", "AL", "NAME", "SERVICE", "RECOVERY", "CHANGED");
  }
  for (std::size_t i = 0; i < m.slaves.count; ++i) {
    const protocol::SlaveRecord& s = m.slaves.slaves[i];
    const char* service = slave_service_name(s.flags);
    const char* recovery = recovery_name(s.recovery);
    char changed[24] = "never";
    if (s.recovery_age_ms != protocol::kRecoveryAgeNever) {
      (void)std::snprintf(changed, sizeof changed, "%.1f s ago", static_cast<double>(s.recovery_age_ms) / 1000.0);
    }
    if (json) {
      char age[16] = "null";
      if (s.recovery_age_ms != protocol::kRecoveryAgeNever) (void)std::snprintf(age, sizeof age, "%u", static_cast<unsigned>(s.recovery_age_ms));
      (void)std::printf(R"(%s{"position":%u,"station":%u,"al_state":"%s","name":)", i == 0 ? "" : ",",
                        static_cast<unsigned>(s.position), static_cast<unsigned>(s.station), al_state_name(s.al_state));
      print_json_string(s.name.data());
      (void)std::printf(R"(,"service":"%s","recovery":"%s","recovery_changed_ms_ago":%s})", service, recovery, age);
    } else {
      (void)std::printf("%-3u 0x%04x  %-6s %-16s %-16s %-12s %s\n", static_cast<unsigned>(s.position), static_cast<unsigned>(s.station),
                        al_state_name(s.al_state), s.name.data(), service, recovery, changed);
    }
  }
  if (json) {
    (void)std::printf("]");
    end_json();
  }
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

const char* planned_slave_name(std::size_t position) noexcept {
  return drivers::slave_end_name(static_cast<std::uint8_t>(position));
}

std::size_t planned_slave_named(const char* text) noexcept {
  constexpr std::size_t kPlanned = drivers::kRobotNetworkPlan.size();
  for (std::size_t p = 0; p < kPlanned; ++p) {
    if (std::strcmp(text, planned_slave_name(p)) == 0) return p;
  }
  char* end = nullptr;
  const long p = std::strtol(text, &end, 10);
  const bool number = text[0] >= '0' && text[0] <= '9' && end != text && *end == '\0';
  return number && p < static_cast<long>(kPlanned) ? static_cast<std::size_t>(p) : kPlanned;
}

const char* slave_service_name(std::uint8_t flags) noexcept {
  return (flags & protocol::kSlaveLost) != 0            ? "lost"
         : (flags & protocol::kSlaveOutOfService) != 0  ? "out of service"
         : (flags & protocol::kSlaveInExchange) != 0    ? "in exchange"
                                                        : "not in exchange";
}


Result<Message> build_slaves(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  Message m;
  m.header.type = args.has("verbose") ? MessageType::get_slave_info : MessageType::get_slaves;
  return m;
}

int print_slaves_answer(const Message& /*request*/, const Message& answer) noexcept {
  const bool json = ctl_output().json;
  if (answer.header.type == MessageType::slaves) {
    print_slaves(answer, json);
  } else if (answer.header.type == MessageType::slave_info) {
    print_slave_info(answer, json);
  } else {
    return ctl_unexpected_answer(answer);
  }
  return 0;
}

Result<Message> build_graph(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  const char* format = args.value("format");
  if (format != nullptr && std::strcmp(format, "text") != 0 && std::strcmp(format, "dot") != 0) {
    return make_error(Errc::invalid_argument, "graph --format: text or dot");
  }
  if (format != nullptr && std::strcmp(format, "dot") == 0 && args.has("json")) {
    return make_error(Errc::invalid_argument, "graph: --format dot or --json, not both");
  }
  Message m;
  m.header.type = MessageType::get_graph;
  return m;
}

int print_graph_answer(const Message& /*request*/, const Message& answer) noexcept {
  if (answer.header.type != MessageType::graph) return ctl_unexpected_answer(answer);
  print_graph(answer, ctl_output().json, ctl_output().format);
  return 0;
}

}  // namespace rescue::app
