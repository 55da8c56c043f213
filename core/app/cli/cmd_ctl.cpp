// rescue-motion ctl: the operator client (docs/operator.md). Modelled on IgH's `ethercat` tool and
// ros2_control's CLI: short verbs, readable tables, --json for scripts; exit status 0 only when the
// robot accepted the command (or answered the query).
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <csignal>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/app/cli/commands.hpp"
#include "core/app/cli/ctl_sdo.hpp"
#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_verbs.hpp"
#include "core/app/config/build_info.hpp"
#include "core/app/config/config_file.hpp"
#include "core/app/operator_protocol/ctl_client.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/rc_task.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/app/links/run_control.hpp"
#include "core/robot/joint_fault.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/master/master.hpp"
#include "fsm/machines/joint_status_dfa.hpp"
#include "hal/files/state_dir.hpp"
#include "hal/net/udp_socket.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

const OptionSpec kOptions[] = {
    {"config", "FILE", "the robot's configuration file, for its key_file, control_port and state_dir (default "
                       "/etc/rescue-motion/rescue-motion.conf when it exists)"},
    {"host", "ADDR", "IPv4 address of the motion PC (default 127.0.0.1)"},
    {"port", "PORT", "control UDP port of the motion PC (default: the configuration's control_port, else 47010)"},
    {"key", "FILE", "pre-shared key file (default: the configuration's key_file, else <state dir>/operator.key, "
                    "where run looks without one)"},
    {"sender", "ID", "this operator's sender id, 1..4294967295 (default 1); one per operator station"},
    {"robot", "ID", "the robot id expected (run's --robot-id); another robot at the address is refused (default: any)"},
    {"task", "N", "RC task for move, hand (default 0)"},
    {"json", nullptr, "print the answer as one JSON object"},
    {"moved", nullptr, "clear: also confirm joints that returned away from their held position"},
    {"timeout", "SECONDS", "how long to wait for the robot's answer (default 2; keygen 10)"},
    {"count", "N", "watch: refresh this many times, then exit (default: until interrupted)"},
    {"interval", "SECONDS", "watch: refresh period (default 0.5)"},
    {"type", "TYPE", "upload, download: the value's type: u8, u16, u32, i8, i16, i32, string or hex "
                     "(default: by the object's size)"},
    {"verbose", nullptr, "slaves: each slave's identity (SII: vendor, product, revision, serial) and AL status code", 'v'},
    {"format", "FORMAT", "graph: text (default) or dot (Graphviz)"},
    {"reset", nullptr, "diag: zero the link error counters (all slaves, or SLAVE)"},
};

const char* state_name(std::uint8_t s) noexcept {
  return s <= 4 ? fsm::to_string(static_cast<fsm::JointState>(s)) : "?";
}
const char* mode_name(std::int8_t m) noexcept {
  switch (m) {
    case 8: return "CSP";
    case 9: return "CSV";
    case 10: return "CST";
    default: return "-";
  }
}
const char* master_state_name(std::uint8_t s) noexcept {
  return s <= 4 ? ecat::to_string(static_cast<ecat::MasterState>(s)) : "?";
}

// The age of the EtherCAT handler's figures (protocol::FiguresAge): JSON members, or a text line when
// they are stale (the handler completed no period for longer than the liveness limit).
void print_age_json(const protocol::FiguresAge& age) noexcept {
  (void)std::printf("\"age_ms\":%" PRIu32 ",\"stale\":%s", age.age_ms, age.stale ? "true" : "false");
}
void print_age_text(const protocol::FiguresAge& age) noexcept {
  if (!age.stale) return;
  (void)std::printf("STALE: the EtherCAT handler has completed no period for %" PRIu32
                    " ms; these figures are that old\n", age.age_ms);
}

void print_status(const Message& m, bool json) noexcept {
  if (json) {
    (void)std::printf("{\"cycle\":%" PRIu64 ",", m.status.cycle);
    print_age_json(m.status.age);
    (void)std::printf(",\"joints\":[");
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const protocol::JointStatusRecord& r = m.status.joints[j];
      (void)std::printf("%s{\"name\":\"%s\",\"state\":\"%s\",\"mode\":\"%s\",\"reachable\":%s,\"lost\":%s,"
                        "\"position_rad\":%.6f,\"velocity_rad_s\":%.6f,\"torque_nm\":%.6f,\"fault\":\"%s\",\"owner\":%s}",
                        j == 0 ? "" : ",", kJoints[j].name, state_name(r.state), mode_name(r.mode),
                        (r.flags & protocol::kFlagReachable) != 0 ? "true" : "false",
                        (r.flags & protocol::kFlagLost) != 0 ? "true" : "false", r.position_rad, r.velocity_rad_s,
                        r.torque_nm, to_string(static_cast<FaultReason>(r.fault)),
                        r.owner == protocol::kNoOwner ? "null" : (r.owner == 0 ? "0" : r.owner == 1 ? "1" : r.owner == 2 ? "2" : "3"));
    }
    (void)std::printf("]}\n");
    return;
  }
  print_age_text(m.status.age);
  (void)std::printf("cycle %" PRIu64 "\n", m.status.cycle);
  (void)std::printf("%-2s %-16s %-10s %-4s %12s %12s %10s  %-24s %s\n", "#", "JOINT", "STATE", "MODE", "POS(rad)",
                    "VEL(rad/s)", "TORQUE(Nm)", "FAULT", "OWNER");
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const protocol::JointStatusRecord& r = m.status.joints[j];
    char state[24];
    (void)std::snprintf(state, sizeof state, "%s%s", state_name(r.state),
                        (r.flags & protocol::kFlagLost) != 0                ? " lost"
                        : (r.flags & protocol::kFlagReachable) == 0         ? " unreach"
                                                                            : "");
    char owner[8];
    (void)std::snprintf(owner, sizeof owner, "%s", r.owner == protocol::kNoOwner ? "-" : "rc");
    if (r.owner != protocol::kNoOwner) (void)std::snprintf(owner, sizeof owner, "rc%u", static_cast<unsigned>(r.owner));
    (void)std::printf("%-2zu %-16s %-10s %-4s %12.4f %12.4f %10.3f  %-24s %s\n", j, kJoints[j].name, state,
                      mode_name(r.mode), r.position_rad, r.velocity_rad_s, r.torque_nm,
                      r.fault == 0 ? "-" : to_string(static_cast<FaultReason>(r.fault)), owner);
  }
}

void print_slaves(const Message& m, bool json) noexcept {
  if (json) {
    (void)std::printf("{");
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
    const char* recovery = ecat::to_string(static_cast<ecat::RecoveryState>(s.recovery));
    char changed[24] = "never";
    if (s.recovery_age_ms != protocol::kRecoveryAgeNever) {
      (void)std::snprintf(changed, sizeof changed, "%.1f s ago", static_cast<double>(s.recovery_age_ms) / 1000.0);
    }
    if (json) {
      char age[16] = "null";
      if (s.recovery_age_ms != protocol::kRecoveryAgeNever) (void)std::snprintf(age, sizeof age, "%u", static_cast<unsigned>(s.recovery_age_ms));
      (void)std::printf(R"(%s{"position":%u,"station":%u,"al_state":"%s","name":"%s","service":"%s","recovery":"%s","recovery_changed_ms_ago":%s})",
                        i == 0 ? "" : ",", static_cast<unsigned>(s.position), static_cast<unsigned>(s.station),
                        al_state_name(s.al_state), s.name.data(), service, recovery, age);
    } else {
      (void)std::printf("%-3u 0x%04x  %-6s %-16s %-16s %-12s %s\n", static_cast<unsigned>(s.position), static_cast<unsigned>(s.station),
                        al_state_name(s.al_state), s.name.data(), service, recovery, changed);
    }
  }
  if (json) (void)std::printf("]}\n");
}

void print_master(const Message& m, bool json) noexcept {
  const protocol::MasterPayload& p = m.master;
  if (json) {
    (void)std::printf("{");
    print_age_json(p.age);
    (void)std::printf(",\"state\":\"%s\",\"cycles\":%" PRIu64 ",\"frames_sent\":%" PRIu64 ",\"frames_lost\":%" PRIu64
                      ",\"late_periods\":%" PRIu64 ",\"dc_deviation_ns\":%" PRId64 ",\"dc_max_deviation_ns\":%" PRId64
                      ",\"datagrams_accepted\":%" PRIu64 ",\"rejected\":{",
                      master_state_name(p.state), p.cycles, p.frames_sent, p.frames_lost, p.late_periods,
                      p.dc_deviation_ns, p.dc_max_deviation_ns, p.datagrams_accepted);
    for (std::size_t i = 0; i < protocol::kRejectionCount; ++i) {
      (void)std::printf("%s\"%s\":%" PRIu64, i == 0 ? "" : ",", protocol::to_string(static_cast<protocol::Rejection>(i)),
                        p.rejected[i]);
    }
    (void)std::printf("}}\n");
    return;
  }
  print_age_text(p.age);
  (void)std::printf("state: %s\ncycles: %" PRIu64 "\nframes sent: %" PRIu64 "\nframes late or lost: %" PRIu64
                    "\nlate periods: %" PRIu64 "\nDC deviation: %" PRId64 " ns (max %" PRId64 " ns)\n"
                    "datagrams accepted: %" PRIu64 "\n",
                    master_state_name(p.state), p.cycles, p.frames_sent, p.frames_lost, p.late_periods,
                    p.dc_deviation_ns, p.dc_max_deviation_ns, p.datagrams_accepted);
  for (std::size_t i = 0; i < protocol::kRejectionCount; ++i) {
    (void)std::printf("datagrams rejected %s: %" PRIu64 "\n", protocol::to_string(static_cast<protocol::Rejection>(i)),
                      p.rejected[i]);
  }
}

void print_figures_json(const char* key, const protocol::TimingFigures& f) noexcept {
  (void)std::printf(R"(,"%s":{"min":%u,"mean":%u,"std":%u,"max":%u,"p99":%u,"p99.9":%u,"p99.99":%u})", key,
                    f.min, f.mean, f.stddev, f.max, f.p99, f.p999, f.p9999);
}

void print_figures_text(const char* what, const protocol::TimingFigures& f) noexcept {
  const auto us = [](std::uint32_t ns) { return static_cast<double>(ns) / 1000.0; };
  (void)std::printf("  %-10s min %.1f  mean %.1f  std %.1f  max %.1f  p99 %.1f  p99.9 %.1f  p99.99 %.1f us\n", what,
                    us(f.min), us(f.mean), us(f.stddev), us(f.max), us(f.p99), us(f.p999), us(f.p9999));
}

void print_tasks(const Message& m, bool json) noexcept {
  if (json) (void)std::printf("{\"tasks\":[");
  // POLICY, PRIO and CPU are what the kernel reports for the task's thread (the task reads them at each
  // publication); TABLE is what the task table asked for (priority/CPU on this machine).
  if (!json) {
    (void)std::printf("%-16s %7s %-6s %4s %3s %7s %10s %7s %12s\n", "TASK", "PID", "POLICY", "PRIO", "CPU", "TABLE",
                      "PERIODS", "MISSED", "MAX EXEC(us)");
  }
  for (std::size_t i = 0; i < m.tasks.count; ++i) {
    const protocol::TaskRecord& t = m.tasks.tasks[i];
    if (json) {
      (void)std::printf("%s{\"name\":\"%s\",\"pid\":%d,\"policy\":\"%s\",\"priority\":%d,\"cpu\":%d,"
                        "\"table_priority\":%d,\"table_cpu\":%d,\"periods\":%" PRIu64 ",\"missed\":%" PRIu64
                        ",\"max_execution_ns\":%" PRIu64,
                        i == 0 ? "" : ",", t.name.data(), t.pid, hal::policy_name(t.policy), t.priority, t.cpu,
                        t.table_priority, t.table_cpu, t.periods, t.missed, t.max_execution_ns);
      print_figures_json("execution_ns", t.execution);
      print_figures_json("wakeup_latency_ns", t.latency);
      (void)std::printf("}");
    } else {
      char table[16];
      (void)std::snprintf(table, sizeof table, "%d/%d", t.table_priority, t.table_cpu);
      (void)std::printf("%-16s %7d %-6s %4d %3d %7s %10" PRIu64 " %7" PRIu64 " %12.1f\n", t.name.data(), t.pid,
                        hal::policy_name(t.policy), t.priority, t.cpu, table, t.periods, t.missed,
                        static_cast<double>(t.max_execution_ns) / 1000.0);
      print_figures_text("execution", t.execution);
      print_figures_text("wake-up", t.latency);
    }
  }
  // The queues between the tasks: what each dropped (or deferred) so far (docs/tasks.md).
  if (json) {
    (void)std::printf("],\"queues\":{");
    for (std::size_t i = 0; i < m.tasks.drop_count; ++i) {
      (void)std::printf("%s\"%s\":%" PRIu64, i == 0 ? "" : ",", i < kDropCounters ? kDropCounterNames[i] : "unknown",
                        m.tasks.dropped[i]);
    }
    (void)std::printf("}}\n");
    return;
  }
  (void)std::printf("queues:");
  for (std::size_t i = 0; i < m.tasks.drop_count; ++i) {
    (void)std::printf(" %s %" PRIu64, i < kDropCounters ? kDropCounterNames[i] : "unknown", m.tasks.dropped[i]);
  }
  (void)std::printf("\n");
}

void print_json_string(const char* s) noexcept;  // below, with ctl's own errors

// ctl version: the robot's program and this client's, like `ethercat version` and `ros2 --version`.
void print_version(const Message& m, bool json) noexcept {
  const protocol::VersionPayload& v = m.version;
  if (json) {
    (void)std::printf(R"({"robot":{"program":)");
    print_json_string(v.program.data());
    (void)std::printf(R"(,"layout_version":%u,"layout_hash":"0x%08x","build_type":)", v.layout_version, v.layout_hash);
    print_json_string(v.build_type.data());
    (void)std::printf(R"(},"client":{"program":)");
    print_json_string(build_program_version());
    (void)std::printf(",\"build_type\":");
    print_json_string(build_type());
    (void)std::printf("}}\n");
    return;
  }
  (void)std::printf("robot:  rescue-motion %s (%s build), shared-memory layout version %u hash 0x%08x\n", v.program.data(),
                    v.build_type.data(), v.layout_version, v.layout_hash);
  (void)std::printf("client: rescue-motion %s (%s build)\n", build_program_version(), build_type());
}

// ctl owner: which RC task owns the motion, whether each task is alive, its phase (like ros2 control
// list_controllers).
void print_owner(const Message& m, bool json) noexcept {
  const protocol::OwnerStatePayload& o = m.owner_state;
  static const char* const kTaskNames[] = {"rescue", "teleop", "task2", "task3"};
  const auto phase_name = [](std::uint8_t p) noexcept {
    return p <= static_cast<std::uint8_t>(kin::RescuePhase::done) ? kin::to_string(static_cast<kin::RescuePhase>(p)) : "?";
  };
  const auto mode_name_of = [](std::uint8_t p) noexcept {
    return p <= static_cast<std::uint8_t>(RcMode::teleop) ? to_string(static_cast<RcMode>(p)) : "?";
  };
  if (json) {
    (void)std::printf("{\"owner\":");
    if (o.owner == protocol::kNoOwner) {
      (void)std::printf("null");
    } else {
      (void)std::printf("%u", o.owner);
    }
    (void)std::printf(",\"generation\":%" PRIu64 ",\"tasks\":[", o.generation);
    bool first = true;
    for (std::size_t k = 0; k < protocol::kMaxRcTasks; ++k) {
      const protocol::RcTaskRecord& t = o.tasks[k];
      if (t.present == 0) continue;
      (void)std::printf(R"(%s{"task":%zu,"name":"%s","owns":%s,"alive":%s,"heartbeat_age_ms":)", first ? "" : ",", k,
                        kTaskNames[k], o.owner == k ? "true" : "false", t.alive != 0 ? "true" : "false");
      if (t.heartbeat_age_ms == 0xFFFFFFFFU) {
        (void)std::printf("null");
      } else {
        (void)std::printf("%u", t.heartbeat_age_ms);
      }
      (void)std::printf(R"(,"mode":"%s","phase":)", mode_name_of(t.mode));
      if (k == 0) {
        (void)std::printf("\"%s\"}", phase_name(t.phase));  // the rescue motion's phase
      } else {
        (void)std::printf("null}");
      }
      first = false;
    }
    (void)std::printf("]}\n");
    return;
  }
  if (o.owner == protocol::kNoOwner) {
    (void)std::printf("owner: none (generation %" PRIu64 "): the joints hold their references\n", o.generation);
  } else {
    (void)std::printf("owner: rc%u (%s), generation %" PRIu64 "\n", o.owner, o.owner < 4 ? kTaskNames[o.owner] : "?",
                      o.generation);
  }
  (void)std::printf("%-4s %-8s %-6s %-6s %-12s %-8s %s\n", "TASK", "NAME", "OWNS", "ALIVE", "HEARTBEAT", "MODE", "PHASE");
  for (std::size_t k = 0; k < protocol::kMaxRcTasks; ++k) {
    const protocol::RcTaskRecord& t = o.tasks[k];
    if (t.present == 0) continue;
    char beat[24];
    if (t.heartbeat_age_ms == 0xFFFFFFFFU) {
      (void)std::snprintf(beat, sizeof beat, "never");
    } else {
      (void)std::snprintf(beat, sizeof beat, "%u ms ago", t.heartbeat_age_ms);
    }
    (void)std::printf("%-4zu %-8s %-6s %-6s %-12s %-8s %s\n", k, kTaskNames[k], o.owner == k ? "yes" : "no",
                      t.alive != 0 ? "yes" : "no", beat, mode_name_of(t.mode), k == 0 ? phase_name(t.phase) : "-");
  }
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
  if (json) {
    (void)std::printf("{\"cycle\":%" PRIu64 ",\"sweeps\":%" PRIu64 ",\"slaves\":[", d.cycle, d.sweeps);
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
    (void)std::printf("]}\n");
    return;
  }
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
    char names[kJointNamesCapacity];
    format_joint_names(r.refused_joints, names, sizeof names);
    (void)std::printf(R"({"command":"%s","accepted":%s,"reason":"%s","joints":"%s","detail":"%s")", verb,
                      accepted ? "true" : "false", protocol::to_string(r.reason), names, r.text.data());
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
    (void)std::printf("}\n");
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
      (void)std::printf("%s: accepted (%s)\n", verb, r.text.data());
    } else {
      (void)std::printf("%s: accepted\n", verb);
    }
  } else {
    (void)std::printf("%s: refused: %s: %s\n", verb, protocol::to_string(r.reason), r.text.data());
  }
  return accepted ? 0 : 1;
}

// The client's own error text when it names what the user typed (one client process: a static buffer).
char g_error_text[2048];
char g_key_note[640] = "";  // the key used, and why that one
bool g_json = false;         // --json: ctl's own errors are a JSON object on stdout too
const char* g_verb = "ctl";  // the verb of this invocation, for those objects
const char* g_format = nullptr;  // graph --format (text or dot)

// A JSON string (quotes and backslashes escaped, control characters dropped).
void print_json_string(const char* s) noexcept {
  (void)std::putchar('"');
  for (; *s != '\0'; ++s) {
    const auto c = static_cast<unsigned char>(*s);
    if (c == '"' || c == '\\') {
      (void)std::putchar('\\');
      (void)std::putchar(c);
    } else if (c >= 0x20) {
      (void)std::putchar(c);
    }
  }
  (void)std::putchar('"');
}

// ctl's own error (before or instead of an answer): one line on stderr, and with --json one object on
// stdout, {"command":VERB,"ok":false,"error":TEXT}. Exit status 1.
int ctl_error(const char* text) noexcept {
  (void)std::fprintf(stderr, "rescue-motion ctl: %s\n", text);
  if (g_json) {
    (void)std::printf("{\"command\":");
    print_json_string(g_verb);
    (void)std::printf(R"(,"ok":false,"error":)");
    print_json_string(text);
    (void)std::printf("}\n");
  }
  return 1;
}

// The configuration file ctl reads (--config FILE, else the package's when it exists): the robot's
// key_file, control_port and state_dir, so ctl looks where `run --config` does.
constexpr const char* kPackageConfig = "/etc/rescue-motion/rescue-motion.conf";
ConfigFile g_ctl_config;
char g_config_path[kConfigTextCapacity] = "";  // empty: none read

Status read_ctl_config(const ParsedArgs& args) noexcept {
  const char* path = args.value("config");
  if (path == nullptr) {
    if (::access(kPackageConfig, F_OK) != 0) return Status::success();  // not installed: defaults
    path = kPackageConfig;
  }
  const ConfigOutcome loaded = load_config_file(path, g_ctl_config);
  if (!loaded.ok) {
    char line[384];
    (void)format_config_error(path, loaded.error, line, sizeof line);
    (void)std::snprintf(g_error_text, sizeof g_error_text, "--config %s", line);
    return make_error(Errc::invalid_argument, g_error_text);
  }
  (void)std::snprintf(g_config_path, sizeof g_config_path, "%s", path);
  return Status::success();
}

// Where the key is, and why there: --key, the configuration's key_file, or the state directory run
// uses without one (not created here).
struct KeyChoice {
  hal::PathBuffer path;
  char source[kConfigTextCapacity + 64];
};

// `make_dir` (keygen): the state directory is created as run creates it.
Result<KeyChoice> choose_key(const ParsedArgs& args, bool make_dir = false) noexcept {
  KeyChoice k;
  if (args.value("key") != nullptr) {
    (void)std::snprintf(k.path.text.data(), k.path.text.size(), "%s", args.value("key"));
    (void)std::snprintf(k.source, sizeof k.source, "--key");
    return k;
  }
  if (g_ctl_config.key_file[0] != '\0') {
    (void)std::snprintf(k.path.text.data(), k.path.text.size(), "%s", g_ctl_config.key_file.data());
    (void)std::snprintf(k.source, sizeof k.source, "key_file of %.200s, where run --config reads it", g_config_path);
    return k;
  }
  const char* option = g_ctl_config.state_dir[0] != '\0' ? g_ctl_config.state_dir.data() : nullptr;
  const Result<hal::StateDir> dir =
      make_dir ? hal::resolve_state_dir(option)
               : hal::choose_state_dir(option, hal::system_state_dir_is_default(),
                                       std::getenv("XDG_STATE_HOME"),  // NOLINT(concurrency-mt-unsafe)
                                       std::getenv("HOME"));           // NOLINT(concurrency-mt-unsafe)
  if (!dir.ok()) return make_error(Errc::not_found, "no default key path: no state directory (give --key FILE)");
  const Result<hal::PathBuffer> joined = hal::join_path(dir.value().path.c_str(), "operator.key");
  if (!joined.ok()) return joined.error();
  k.path = joined.value();
  if (option != nullptr) {
    (void)std::snprintf(k.source, sizeof k.source,
                        "the state directory (state_dir of %.200s), where run looks without --key or key_file", g_config_path);
  } else {
    (void)std::snprintf(k.source, sizeof k.source,
                        "the state directory (%s), where run looks without --key or key_file", dir.value().source);
  }
  return k;
}

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
  (void)std::snprintf(g_error_text, sizeof g_error_text, "%s: '%s' (in '%s'); the joints: %s%s", error.what, item, list, names,
                      all_allowed ? " (or all)" : "");
  return make_error(Errc::invalid_argument, g_error_text, error.detail0);
}

Result<JointMask> joints_argument(const ParsedArgs& args, std::size_t index) noexcept {
  if (args.positional_count() <= index || std::strcmp(args.positional(index), "all") == 0) return kAllJoints;
  Result<JointMask> joints = parse_joint_names(args.positional(index));
  if (!joints.ok()) return bad_joint_names(args.positional(index), joints.error(), true);
  return joints;
}

Result<CtlTarget> target_of(const ParsedArgs& args) noexcept {
  CtlTarget t;
  const Result<std::uint32_t> address = hal::parse_ipv4(args.value("host") != nullptr ? args.value("host") : "127.0.0.1");
  if (!address.ok()) return make_error(Errc::invalid_argument, "--host must be an IPv4 address");
  t.address = address.value();
  const Result<std::int64_t> port = args.integer("port", 47010, 1, 65535);
  if (!port.ok()) return make_error(Errc::invalid_argument, "--port must be 1..65535");
  t.port = static_cast<std::uint16_t>(port.value());
  const Result<std::int64_t> sender = args.integer("sender", 1, 1, 0xFFFFFFFFLL);
  if (!sender.ok()) return make_error(Errc::invalid_argument, "--sender must be 1..4294967295");
  t.sender = static_cast<std::uint32_t>(sender.value());
  const Result<std::int64_t> robot = args.integer("robot", protocol::kAnyRobot, 0, 999'999'999);
  if (!robot.ok()) return make_error(Errc::invalid_argument, "--robot must be 1..999999999");
  t.robot = static_cast<std::uint32_t>(robot.value());
  const Result<double> timeout = args.number("timeout", 2.0, 0.01, 60.0);
  if (!timeout.ok()) return make_error(Errc::invalid_argument, "--timeout must be 0.01..60 seconds");
  t.timeout_ms = static_cast<int>(timeout.value() * 1000.0);
  if (g_ctl_config.has_control_port && args.value("port") == nullptr) t.port = g_ctl_config.control_port;
  const Result<KeyChoice> choice = choose_key(args);
  if (!choice.ok()) return choice.error();
  const hal::PathBuffer& path = choice.value().path;
  hal::FileProblem why;
  const Result<protocol::Key> key = protocol::load_key_file(path.c_str(), why);
  if (!key.ok()) {
    if (key.error().code == Errc::not_found) {
      (void)std::snprintf(g_error_text, sizeof g_error_text,
                          "key file %.255s (%.320s): %.100s; the robot's key is its configuration's key_file (run --config), "
                          "else --key, else <state dir>/operator.key: copy that file here, or make a new one with "
                          "`rescue-motion ctl keygen --key %.255s` and start run with --key %.255s",
                          path.c_str(), choice.value().source, why.c_str(), path.c_str(), path.c_str());
    } else {
      (void)std::snprintf(g_error_text, sizeof g_error_text, "key file refused: %.400s (%.320s); the key file cannot be used",
                          why.c_str(), choice.value().source);
    }
    return make_error(key.error().code, g_error_text);
  }
  t.key = key.value();
  (void)std::snprintf(g_key_note, sizeof g_key_note, "key %.255s from %.320s", path.c_str(), choice.value().source);
  return t;
}

int keygen(const ParsedArgs& args) noexcept {
  const Result<KeyChoice> choice = choose_key(args, true);
  if (!choice.ok()) return ctl_error(choice.error().what);
  const hal::PathBuffer& path = choice.value().path;
  const Status made = protocol::create_key_file(path.c_str());
  if (!made.ok()) {
    (void)std::snprintf(g_error_text, sizeof g_error_text, "keygen %.255s (%.320s): %.100s", path.c_str(), choice.value().source,
                        made.error().what);
    return ctl_error(g_error_text);
  }
  if (g_json) {
    (void)std::printf(R"({"command":"keygen","ok":true,"key_file":)");
    print_json_string(path.c_str());
    (void)std::printf(R"(,"mode":"0600","bytes":32,"source":)");
    print_json_string(choice.value().source);
    (void)std::printf("}\n");
    return 0;
  }
  (void)std::printf("keygen: wrote a new 32-byte key to %s (mode 0600); copy it to the motion PC and every operator station\n",
                    path.c_str());
  return 0;
}

int exchange_and_print(const char* verb, const CtlTarget& target, const Message& request, bool json) noexcept {
  const Result<Message> answer = ctl_exchange(target, request);
  if (!answer.ok()) {
    if (answer.error().code == Errc::refused) {  // another robot id than --robot
      (void)std::snprintf(g_error_text, sizeof g_error_text,
                          "%.32s: refused: the robot at that address is robot %u, not robot %u (--robot)", verb,
                          static_cast<unsigned>(answer.error().detail0), static_cast<unsigned>(target.robot));
    } else {
      (void)std::snprintf(g_error_text, sizeof g_error_text, "%.32s: refused: %.200s (%.640s)", verb, answer.error().what,
                          g_key_note);
    }
    return ctl_error(g_error_text);
  }
  const Message& m = answer.value();
  switch (m.header.type) {
    case MessageType::status: print_status(m, json); return 0;
    case MessageType::slaves: print_slaves(m, json); return 0;
    case MessageType::master: print_master(m, json); return 0;
    case MessageType::tasks: print_tasks(m, json); return 0;
    case MessageType::diag: print_diag(m, json); return 0;
    case MessageType::reply:
      return request.header.type == MessageType::diag_reset ? print_diag_reset_reply(request, m, json) : print_reply(verb, m, json);
    case MessageType::slave_info: return print_slave_info(m, json);
    case MessageType::graph: return print_graph(m, json, g_format);
    case MessageType::version: print_version(m, json); return 0;
    case MessageType::owner_state: print_owner(m, json); return 0;
    case MessageType::sdo_result: return print_sdo_result(m, json);
    default: return ctl_error("unexpected answer type");
  }
}

Result<Message> build_request(const char* verb, const ParsedArgs& args) noexcept {
  // slaves -v, graph, diag --reset (ctl_network.cpp); the rest here.
  Result<Message> network = build_network_request(verb, args);
  if (network.ok() || network.error().code != Errc::not_found) return network;
  Message m;
  const std::size_t n = args.positional_count();
  struct Simple {
    const char* verb;
    MessageType type;
  };
  static constexpr Simple kQueries[] = {{"status", MessageType::get_status}, {"slaves", MessageType::get_slaves},
                                        {"master", MessageType::get_master}, {"tasks", MessageType::get_tasks},
                                        {"diag", MessageType::get_diag}};
  for (const Simple& q : kQueries) {
    if (std::strcmp(verb, q.verb) == 0) {
      m.header.type = q.type;
      return m;
    }
  }
  static constexpr Simple kJointVerbs[] = {{"init", MessageType::initialize}, {"enable", MessageType::enable},
                                           {"disable", MessageType::disable}, {"hold", MessageType::hold},
                                           {"clear", MessageType::clear_joints}};
  for (const Simple& q : kJointVerbs) {
    if (std::strcmp(verb, q.verb) != 0) continue;
    if (q.type == MessageType::clear_joints && n < 2) return make_error(Errc::invalid_argument, "clear JOINTS: name the repaired joints");
    const Result<JointMask> joints = joints_argument(args, 1);
    if (!joints.ok()) return joints.error();
    m.header.type = q.type;
    if (args.has("moved")) {
      if (q.type != MessageType::clear_joints) return make_error(Errc::invalid_argument, "--moved goes with clear JOINTS");
      m.header.type = MessageType::clear_moved;
    }
    m.joints.joints = joints.value();
    return m;
  }
  const Result<std::int64_t> task = args.integer("task", 0, 0, static_cast<std::int64_t>(protocol::kMaxRcTasks) - 1);
  if (!task.ok()) return make_error(Errc::invalid_argument, "--task must be 0..3");
  if (std::strcmp(verb, "mode") == 0) {
    if (n != 3) return make_error(Errc::invalid_argument, "mode JOINT MODE (MODE: csp, csv or cst)");
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
  if (std::strcmp(verb, "move") == 0) {
    if (n != 3) return make_error(Errc::invalid_argument, "move EFFECTOR POSE (EFFECTOR: left or right; POSE: x,y,z,roll,pitch,yaw in m and rad)");
    m.header.type = MessageType::move_effector;
    m.move.task = static_cast<std::uint8_t>(task.value());
    if (std::strcmp(args.positional(1), "left") == 0) m.move.effector = protocol::Effector::left_hand;
    else if (std::strcmp(args.positional(1), "right") == 0) m.move.effector = protocol::Effector::right_hand;
    else return make_error(Errc::invalid_argument, "EFFECTOR must be left or right");
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
  if (std::strcmp(verb, "hand") == 0) {
    if (n != 3) return make_error(Errc::invalid_argument, "hand left|right open|close");
    m.header.type = MessageType::hand;
    m.hand.task = static_cast<std::uint8_t>(task.value());
    if (std::strcmp(args.positional(1), "left") == 0) m.hand.hand = protocol::Effector::left_hand;
    else if (std::strcmp(args.positional(1), "right") == 0) m.hand.hand = protocol::Effector::right_hand;
    else return make_error(Errc::invalid_argument, "hand: left or right");
    if (std::strcmp(args.positional(2), "open") == 0) m.hand.action = protocol::HandAction::open;
    else if (std::strcmp(args.positional(2), "close") == 0) m.hand.action = protocol::HandAction::close;
    else return make_error(Errc::invalid_argument, "hand: open or close");
    return m;
  }
  if (std::strcmp(verb, "owner") == 0 && n == 1) {  // who owns the motion (like list_controllers)
    m.header.type = MessageType::get_owner;
    return m;
  }
  if (std::strcmp(verb, "version") == 0) {
    m.header.type = MessageType::get_version;
    return m;
  }
  if (std::strcmp(verb, "owner") == 0) {
    if (n != 2) return make_error(Errc::invalid_argument, "owner [TASK] (TASK: 0..3)");
    char* end = nullptr;
    const long t = std::strtol(args.positional(1), &end, 10);
    if (end == args.positional(1) || *end != '\0' || t < 0 || t >= static_cast<long>(protocol::kMaxRcTasks)) {
      return make_error(Errc::invalid_argument, "owner TASK: 0..3");
    }
    m.header.type = MessageType::take_owner;
    m.owner.task = static_cast<std::uint8_t>(t);
    return m;
  }
  return make_error(Errc::invalid_argument, "unknown verb (see rescue-motion ctl --help)");
}

// The whole command within --timeout (docs/security.md): the exchange has its own deadline, and
// this watchdog covers every other phase (the key and configuration files, the state directory),
// so nothing found at a path and no system call can make ctl wait past it.
constexpr double kKeygenDefaultTimeoutSeconds = 10.0;

void ctl_deadline_passed(int /*signal*/) {
  static const char kText[] = "rescue-motion ctl: stopped: no result within --timeout (a file or the network blocked)\n";
  (void)!::write(STDERR_FILENO, kText, sizeof kText - 1);
  ::_exit(1);
}

void arm_ctl_deadline(double seconds) noexcept {
  struct sigaction action {};
  action.sa_handler = ctl_deadline_passed;
  (void)::sigaction(SIGALRM, &action, nullptr);
  itimerval timer{};
  const double total = seconds + 0.5;  // the exchange's own deadline comes first
  timer.it_value.tv_sec = static_cast<time_t>(total);
  timer.it_value.tv_usec = static_cast<suseconds_t>((total - static_cast<double>(timer.it_value.tv_sec)) * 1e6);
  (void)::setitimer(ITIMER_REAL, &timer, nullptr);
}

void disarm_ctl_deadline() noexcept {
  itimerval timer{};
  (void)::setitimer(ITIMER_REAL, &timer, nullptr);
}

int ctl_main(const ParsedArgs& args) {
  const char* verb = args.positional(0);
  g_json = args.has("json");
  g_format = args.value("format");
  g_verb = verb != nullptr ? verb : "ctl";
  if (verb == nullptr || !is_ctl_verb(verb)) return ctl_error("unknown verb (see rescue-motion ctl --help)");
  // keygen waits for no robot, only for its key to reach the disk (fsync): on a busy laptop that
  // alone can take seconds, so its default allowance is longer; --timeout still bounds it.
  const double default_deadline = std::strcmp(verb, "keygen") == 0 ? kKeygenDefaultTimeoutSeconds : 2.0;
  const Result<double> deadline = args.number("timeout", default_deadline, 0.01, 60.0);
  arm_ctl_deadline(deadline.ok() ? deadline.value() : default_deadline);
  if (!protocol::init_crypto().ok()) return ctl_error("libsodium could not be initialised");
  const Status config = read_ctl_config(args);
  if (!config.ok()) return ctl_error(config.error().what);
  for (const CtlVerbOption& o : kCtlVerbOptions) {
    const bool belongs = std::any_of(std::begin(o.verbs), std::end(o.verbs),
                                     [verb](const char* v) { return v != nullptr && std::strcmp(v, verb) == 0; });
    if (args.has(o.option) && !belongs) return ctl_error(o.error);
  }
  if (std::strcmp(verb, "keygen") == 0) return keygen(args);
  if (is_sdo_verb(verb)) {
    const Result<CtlTarget> sdo_target = target_of(args);
    if (!sdo_target.ok()) return ctl_error(sdo_target.error().what);
    const Result<Message> sdo = build_sdo_request(verb, args, sdo_target.value());
    if (!sdo.ok()) return ctl_error(sdo.error().what);
    return exchange_and_print(verb, sdo_target.value(), sdo.value(), g_json);
  }
  const bool watch = std::strcmp(verb, "watch") == 0;
  const Result<Message> request = build_request(watch ? "status" : verb, args);
  if (!request.ok()) return ctl_error(request.error().what);
  const Result<CtlTarget> target = target_of(args);
  if (!target.ok()) return ctl_error(target.error().what);
  const bool json = g_json;
  if (!watch) return exchange_and_print(verb, target.value(), request.value(), json);
  disarm_ctl_deadline();  // watch runs until --count: each exchange keeps its own deadline
  const Result<std::int64_t> count = args.integer("count", 0, 0, 1'000'000'000);
  const Result<double> interval = args.number("interval", 0.5, 0.05, 3600.0);
  if (!count.ok() || !interval.ok()) return ctl_error("watch: --count N and --interval SECONDS");
  hal::MonotonicClock clock;
  hal::Nanoseconds next = clock.now();
  for (std::int64_t i = 0; count.value() == 0 || i < count.value(); ++i) {
    if (!json) (void)std::printf("\033[H\033[2J");  // refreshed in place
    const int status = exchange_and_print("watch", target.value(), request.value(), json);
    (void)std::fflush(stdout);
    if (status != 0) return status;
    next += static_cast<hal::Nanoseconds>(interval.value() * 1e9);
    clock.sleep_until(next);
  }
  return 0;
}

}  // namespace

const CommandSpec kCtlCommand{
    "ctl", "ctl [OPTIONS] VERB [ARGS]", "operator client: query and command a running firmware (docs/operator.md)",
    "Verbs:\n"
    "  status | slaves | master | tasks     the robot's joints, EtherCAT slaves, master counters, tasks\n"
    "  slaves -v                            per slave: SII vendor, product, revision, serial; AL status code\n"
    "  diag                                 link-quality counters per slave and port, warnings naming the cable\n"
    "  diag --reset [SLAVE]                 zero the link error counters (all slaves, or SLAVE: name or position)\n"
    "  graph [--format dot]                 the topology now: chains on junction ports, joints behind each cable\n"
    "  watch                                status, refreshed in place (--interval, --count)\n"
    "  init [JOINTS]                        'initialize robot': mode, reference := position, enable\n"
    "  enable [JOINTS] | disable [JOINTS]   DFA enable / disable (JOINTS: comma-separated names or all)\n"
    "  hold [JOINTS]                        Enabled joints stop and hold where they stand\n"
    "  mode JOINT MODE                      select csp, csv or cst\n"
    "  clear JOINTS [--moved]               clear joints after repair (error-joints file), then reset;\n"
    "                                       --moved: also confirm joints back away from their held position\n"
    "  move EFFECTOR POSE                   left|right x,y,z,roll,pitch,yaw to RC task --task\n"
    "  hand left|right open|close           to RC task --task\n"
    "  owner TASK                           RC task TASK takes the motion\n"
    "  owner                                which RC task owns the motion, each task alive or not, its phase\n"
    "  version                              the robot's program version, layout and build type, and ctl's own\n"
    "  upload JOINT INDEX:SUB               read a CoE object of the joint's drive (SDO; e.g. 0x100A:00), --type\n"
    "  download JOINT INDEX:SUB VALUE       write one; objects of the cyclic image are refused with the reason\n"
    "  keygen                               create a new key file (--key FILE), mode 0600\n"
    "Exit status 0 only when the robot accepted the command or answered the query.",
    Span<const OptionSpec>(kOptions), 1, 4, ctl_main};

}  // namespace rescue::app
