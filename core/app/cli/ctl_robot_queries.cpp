// ctl's queries about the robot as a whole (docs/operator.md): status (the joints, like ros2 control's
// list_hardware_interfaces), master (the master's counters), tasks (the real-time tasks, their
// timing and the queues' drops), version and owner (which RC task owns the motion). Each answer
// printed as a table or as one JSON object (ctl_output.hpp's envelope).
#include "core/app/cli/ctl_robot_queries.hpp"

#include <cinttypes>
#include <cstdio>

#include "core/app/cli/ctl_output.hpp"
#include "core/app/config/build_info.hpp"
#include "core/app/links/run_control.hpp"
#include "core/app/tasks/rc_task_frame.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/robot/joint_fault.hpp"
#include "ecat/master/master.hpp"
#include "fsm/machines/joint_status_dfa.hpp"
#include "hal/rt/rt_setup.hpp"

namespace rescue::app {
namespace {

using protocol::Message;

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


void print_figures_json(const char* key, const protocol::TimingFigures& f) noexcept {
  (void)std::printf(R"(,"%s":{"min":%u,"mean":%u,"std":%u,"max":%u,"p99":%u,"p99.9":%u,"p99.99":%u})", key,
                    f.min, f.mean, f.stddev, f.max, f.p99, f.p999, f.p9999);
}

void print_figures_text(const char* what, const protocol::TimingFigures& f) noexcept {
  const auto us = [](std::uint32_t ns) { return static_cast<double>(ns) / 1000.0; };
  (void)std::printf("  %-10s min %.1f  mean %.1f  std %.1f  max %.1f  p99 %.1f  p99.9 %.1f  p99.99 %.1f us\n", what,
                    us(f.min), us(f.mean), us(f.stddev), us(f.max), us(f.p99), us(f.p999), us(f.p9999));
}

}  // namespace

void print_status(const Message& m, bool json) noexcept {
  if (json) {
    begin_json(true);
    (void)std::printf(",\"cycle\":%" PRIu64, m.status.cycle);
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
    (void)std::printf("]");
    end_json();
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

void print_master(const Message& m, bool json) noexcept {
  const protocol::MasterPayload& p = m.master;
  if (json) {
    begin_json(true);
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
    (void)std::printf("}");
    end_json();
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

void print_tasks(const Message& m, bool json) noexcept {
  if (json) {
    begin_json(true);
    print_age_json(m.tasks.age);
    (void)std::printf(",\"tasks\":[");
  }
  // POLICY, PRIO and CPU are what the kernel reports for the task's thread (the task reads them at each
  // publication); TABLE is what the task table asked for (priority/CPU on this machine).
  if (!json) {
    print_age_text(m.tasks.age);
    (void)std::printf("%-16s %7s %7s %-6s %4s %3s %7s %8s %11s %10s %7s %12s\n", "TASK", "PID", "TID", "POLICY", "PRIO",
                      "CPU", "TABLE", "RESTARTS", "UPTIME(s)", "PERIODS", "MISSED", "MAX EXEC(us)");
  }
  for (std::size_t i = 0; i < m.tasks.count; ++i) {
    const protocol::TaskRecord& t = m.tasks.tasks[i];
    if (json) {
      (void)std::printf("%s{\"name\":", i == 0 ? "" : ",");
      print_json_string(t.name.data());
      (void)std::printf(",\"pid\":%d,\"tid\":%d,\"policy\":\"%s\",\"priority\":%d,\"cpu\":%d,"
                        "\"table_priority\":%d,\"table_cpu\":%d,\"restarts\":%u,\"uptime_ms\":",
                        t.pid, t.tid, hal::policy_name(t.policy), t.priority, t.cpu, t.table_priority, t.table_cpu,
                        static_cast<unsigned>(t.restarts));
      if (t.uptime_ms == protocol::kUptimeUnknown) {
        (void)std::printf("null");
      } else {
        (void)std::printf("%u", t.uptime_ms);
      }
      (void)std::printf(",\"periods\":%" PRIu64 ",\"missed\":%" PRIu64 ",\"max_execution_ns\":%" PRIu64, t.periods,
                        t.missed, t.max_execution_ns);
      print_figures_json("execution_ns", t.execution);
      print_figures_json("wakeup_latency_ns", t.latency);
      (void)std::printf("}");
    } else {
      char table[16];
      (void)std::snprintf(table, sizeof table, "%d/%d", t.table_priority, t.table_cpu);
      char uptime[16] = "n/a";
      if (t.uptime_ms != protocol::kUptimeUnknown) {
        (void)std::snprintf(uptime, sizeof uptime, "%.1f", static_cast<double>(t.uptime_ms) / 1000.0);
      }
      (void)std::printf("%-16s %7d %7d %-6s %4d %3d %7s %8u %11s %10" PRIu64 " %7" PRIu64 " %12.1f\n", t.name.data(), t.pid,
                        t.tid, hal::policy_name(t.policy), t.priority, t.cpu, table, static_cast<unsigned>(t.restarts),
                        uptime, t.periods, t.missed, static_cast<double>(t.max_execution_ns) / 1000.0);
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
    (void)std::printf("}");
    end_json();
    return;
  }
  (void)std::printf("queues:");
  for (std::size_t i = 0; i < m.tasks.drop_count; ++i) {
    (void)std::printf(" %s %" PRIu64, i < kDropCounters ? kDropCounterNames[i] : "unknown", m.tasks.dropped[i]);
  }
  (void)std::printf("\n");
}

// ctl version: the robot's program and this client's, like `ethercat version` and `ros2 --version`.
void print_version(const Message& m, bool json) noexcept {
  const protocol::VersionPayload& v = m.version;
  if (json) {
    begin_json(true);
    (void)std::printf(R"(,"robot":{"program":)");
    print_json_string(v.program.data());
    (void)std::printf(R"(,"layout_version":%u,"layout_hash":"0x%08x","build_type":)", v.layout_version, v.layout_hash);
    print_json_string(v.build_type.data());
    (void)std::printf(R"(},"client":{"program":)");
    print_json_string(build_program_version());
    (void)std::printf(",\"build_type\":");
    print_json_string(build_type());
    (void)std::printf("}");
    end_json();
    return;
  }
  (void)std::printf("robot:  rescue-motion ");
  print_text_string(v.program.data());
  (void)std::printf(" (");
  print_text_string(v.build_type.data());
  (void)std::printf(" build), shared-memory layout version %u hash 0x%08x\n", v.layout_version, v.layout_hash);
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
    begin_json(true);
    print_age_json(o.age);
    (void)std::printf(",\"owner\":");
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
    (void)std::printf("]");
    end_json();
    return;
  }
  print_age_text(o.age);
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

}  // namespace rescue::app
