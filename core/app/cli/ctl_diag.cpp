// ctl diag (link-quality counters per slave and port, like IgH's `ethercat crc`, with warnings naming
// the cable) and ctl diag --reset [SLAVE] (zero the link error counters): request and printed answer.
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/master/link_diagnostics.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

constexpr std::size_t kPlanned = drivers::kRobotNetworkPlan.size();

// The slave (position) SLAVE names: a slave's name or its position.
Result<std::uint32_t> slave_argument(const char* text) noexcept {
  const std::size_t p = planned_slave_named(text);
  if (p < kPlanned) return std::uint32_t{1} << p;
  return make_error(Errc::invalid_argument, "diag --reset SLAVE: a slave's name (ctl slaves) or its position 0..22");
}

// The slave at the other end of the cable on `slave`'s `port` (ecat::cable_peer on the robot's plan).
const char* cable_peer_name(std::size_t slave, unsigned port) noexcept {
  return drivers::slave_end_name(ecat::cable_peer(drivers::kRobotNetworkPlan, slave, port));
}

// A port's warning: "rising" (errors rising now), "earlier" (warned since bring-up, quiet now), "none".
const char* warning_state(const protocol::DiagSlaveRecord& s, unsigned port) noexcept {
  if ((s.warned & (1U << port)) != 0) return "rising";
  return (s.warned_before & (1U << port)) != 0 ? "earlier" : "none";
}

// Like IgH's `ethercat crc`: per slave and port invalid frames / RX errors / forwarded RX errors /
// lost links, then the processing-unit and PDI errors; '!' marks a port in warning, whose cable is
// named below the table ('*': warned earlier, quiet now).
void print_diag(const Message& m, bool json) noexcept {
  const protocol::DiagPayload& d = m.diag;
  const protocol::FiguresAge age{d.stale != 0, d.age_ms};
  if (json) {
    begin_json(true);
    print_age_json(age);
    (void)std::printf(",\"cycle\":%" PRIu64 ",\"sweeps\":%" PRIu64 ",\"slaves\":[", d.cycle, d.sweeps);
    for (std::size_t i = 0; i < d.count; ++i) {
      const protocol::DiagSlaveRecord& s = d.slaves[i];
      (void)std::printf(R"(%s{"position":%zu,"name":"%s","ports":[)", i == 0 ? "" : ",", i, drivers::slave_end_name(static_cast<std::uint8_t>(i)));
      for (unsigned n = 0; n < protocol::kDiagPorts; ++n) {
        const protocol::DiagPortRecord& p = s.ports[n];
        (void)std::printf(R"(%s{"port":%u,"invalid_frames":%u,"rx_errors":%u,"forwarded_rx_errors":%u,"lost_links":%u,"warning":"%s","cable_to":"%s"})",
                          n == 0 ? "" : ",", n, static_cast<unsigned>(p.invalid_frames), static_cast<unsigned>(p.rx_errors),
                          static_cast<unsigned>(p.forwarded_errors), static_cast<unsigned>(p.lost_links),
                          warning_state(s, n), cable_peer_name(i, n));
      }
      (void)std::printf(R"(],"processing_unit_errors":%u,"pdi_errors":%u,"reads":%u})",
                        static_cast<unsigned>(s.processing_unit_errors), static_cast<unsigned>(s.pdi_errors),
                        static_cast<unsigned>(s.reads));
    }
    (void)std::printf("]");
    end_json();
    return;
  }
  print_age_text(age);
  if (d.cycle == 0) {
    (void)std::printf("no diagnostics sweep completed yet (the master reads them in OP)\n");
    return;
  }
  (void)std::printf("cycle %" PRIu64 ", %" PRIu64 " sweeps; per port: invalid frames/RX errors/forwarded RX errors/lost links\n",
                    d.cycle, d.sweeps);
  (void)std::printf("%-3s %-16s", "POS", "SLAVE");
  for (unsigned n = 0; n < protocol::kDiagPorts; ++n) (void)std::printf(" %-17s", n == 0 ? "PORT 0" : n == 1 ? "PORT 1" : n == 2 ? "PORT 2" : "PORT 3");
  (void)std::printf(" %5s %5s %6s\n", "EPU", "PDI", "READS");
  for (std::size_t i = 0; i < d.count; ++i) {
    const protocol::DiagSlaveRecord& s = d.slaves[i];
    (void)std::printf("%-3zu %-16s", i, drivers::slave_end_name(static_cast<std::uint8_t>(i)));
    for (unsigned n = 0; n < protocol::kDiagPorts; ++n) {
      const protocol::DiagPortRecord& p = s.ports[n];
      char cell[32];  // four 16-bit counters (5 digits each), three slashes, a mark and the NUL
      (void)std::snprintf(cell, sizeof cell, "%u/%u/%u/%u%s", static_cast<unsigned>(p.invalid_frames),
                          static_cast<unsigned>(p.rx_errors), static_cast<unsigned>(p.forwarded_errors),
                          static_cast<unsigned>(p.lost_links),
                          (s.warned & (1U << n)) != 0 ? " !" : (s.warned_before & (1U << n)) != 0 ? " *" : "");
      (void)std::printf(" %-17s", cell);
    }
    (void)std::printf(" %5u %5u %6u\n", static_cast<unsigned>(s.processing_unit_errors), static_cast<unsigned>(s.pdi_errors),
                      static_cast<unsigned>(s.reads));
  }
  for (std::size_t i = 0; i < d.count; ++i) {
    for (unsigned n = 0; n < protocol::kDiagPorts; ++n) {
      const char* state = warning_state(d.slaves[i], n);
      if (std::strcmp(state, "none") == 0) continue;
      (void)std::printf("warning (%s): receive errors on %s port %u: check the cable between %s and %s\n",
                        std::strcmp(state, "rising") == 0 ? "!, rising now" : "*, earlier, quiet now",
                        drivers::slave_end_name(static_cast<std::uint8_t>(i)), n, cable_peer_name(i, n),
                        drivers::slave_end_name(static_cast<std::uint8_t>(i)));
    }
  }
}

void print_diag_reset_reply(const Message& request, const Message& m, bool json) noexcept {
  const protocol::ReplyPayload& r = m.reply;
  const bool accepted = r.outcome == protocol::Outcome::accepted;
  const std::uint32_t slaves = request.diag_reset.slaves;
  const bool all = slaves == (std::uint32_t{1} << kPlanned) - 1;
  const char* one = "";
  for (std::size_t p = 0; p < kPlanned && !all; ++p) {
    if ((slaves & (std::uint32_t{1} << p)) != 0) one = planned_slave_name(p);
  }
  if (json) {
    begin_json(accepted);
    (void)std::printf(R"(,"accepted":%s,"reason":"%s","slaves":)", accepted ? "true" : "false", protocol::to_string(r.reason));
    if (all) {
      (void)std::printf("\"all\"");
    } else {
      (void)std::printf("\"%s\"", one);
    }
    (void)std::printf(",\"detail\":");
    print_json_string(r.text.data());
    end_json();
  } else if (accepted) {
    (void)std::printf("diag --reset: %s: ", all ? "all slaves" : one);
    print_text_string(r.text.data());
    (void)std::printf("\n");
  } else {
    (void)std::printf("diag --reset: refused: %s: ", protocol::to_string(r.reason));
    print_text_string(r.text.data());
    (void)std::printf("\n");
  }
}


}  // namespace

Result<Message> build_diag(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  Message m;
  if (!args.has("reset")) {
    if (args.positional_count() != 1) return make_error(Errc::invalid_argument, "diag [--reset [SLAVE]]");
    m.header.type = MessageType::get_diag;
    return m;
  }
  ctl_output().verb = "diag --reset";
  m.header.type = MessageType::diag_reset;
  m.diag_reset.slaves = (std::uint32_t{1} << kPlanned) - 1;
  if (args.positional_count() == 2) {
    const Result<std::uint32_t> one = slave_argument(args.positional(1));
    if (!one.ok()) return one.error();
    m.diag_reset.slaves = one.value();
  }
  return m;
}

int print_diag_answer(const Message& request, const Message& answer) noexcept {
  const bool json = ctl_output().json;
  if (request.header.type == MessageType::get_diag && answer.header.type == MessageType::diag) {
    print_diag(answer, json);
    return 0;
  }
  if (request.header.type == MessageType::diag_reset && answer.header.type == MessageType::reply) {
    print_diag_reset_reply(request, answer, json);
    return answer.reply.outcome == protocol::Outcome::accepted ? 0 : static_cast<int>(CtlExit::refused);
  }
  return ctl_unexpected_answer(answer);
}

}  // namespace rescue::app
