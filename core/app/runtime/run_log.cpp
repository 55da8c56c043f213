// The logger's print passes (run_log.hpp).
#include "core/app/runtime/run_log.hpp"

#include <cinttypes>
#include <cstdio>

#include "core/app/runtime/run_context.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "ecat/master/al_control.hpp"
#include "ecat/master/bring_up_report.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::app::runner {
namespace {

void print_handler_event(const HandlerEvent& e, hal::Nanoseconds start) noexcept {
  char names[kJointNamesCapacity];
  format_joint_names(e.joints, names, sizeof names);
  const double t = seconds(e.time - start);
  switch (e.kind) {
    case HandlerEventKind::link_report:
      if (e.link.kind == ecat::LinkEventKind::port_errors) {
        // found: port, the slave at the cable's other end, errors so far (ecat/master/link_diagnostics.hpp).
        const std::uint8_t slave = drivers::first_slave(e.link.slaves);
        (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": receive errors rising on %s port %" PRIu32
                          " (%" PRIu32 " so far): check the cable between %s and %s\n",
                          t, e.cycle, drivers::slave_end_name(slave), e.link.found[0], e.link.found[2],
                          drivers::slave_end_name(static_cast<std::uint8_t>(e.link.found[1])), drivers::slave_end_name(slave));
        break;
      }
      if (e.link.kind == ecat::LinkEventKind::watchdog_expired) {
        // Not a link fault: the master itself was silent (host stall) past the SyncManager watchdog.
        (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": SyncManager watchdogs expired after %" PRIu32
                          " ms without frames (host stall, not a link fault), re-arming: %s; each comes back "
                          "holding its actual position, and the motion waits for the operator (a Motion owner is "
                          "released: ctl owner N moves again)\n",
                          t, e.cycle, e.link.found[0], names);
        break;
      }
      if (e.link.kind == ecat::LinkEventKind::not_operational) {
        // Reachable but out of OP (the AL state watch, or a probe): its AL status and code by name.
        (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": link not operational: %s in %s%s, AL status code 0x%04X %s"
                          " (first seen in cycle %" PRIu64 ")\n",
                          t, e.cycle, names, ecat::reg::to_string(static_cast<ecat::reg::AlState>(e.link.al_status & ecat::reg::kAlStateMask)),
                          (e.link.al_status & ecat::reg::kAlErrorBit) != 0 ? " with error" : "", e.link.al_status_code,
                          ecat::reg::explain_al_status_code(e.link.al_status_code), e.link.detected_cycle);
        break;
      }
      if (e.link.kind == ecat::LinkEventKind::recovery_failed) {
        // found: the recovery state that timed out, failures in a row, hold-off before the next attempt.
        (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": recovery failed: %s (in %s, attempt %" PRIu32
                          " in a row), trying again from the start in %" PRIu32 " ms\n",
                          t, e.cycle, names, ecat::to_string(static_cast<ecat::RecoveryState>(e.link.found[0])), e.link.found[1],
                          e.link.found[2]);
        break;
      }
      if (e.link.kind == ecat::LinkEventKind::rearmed) {
        (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": back in OP after the watchdog: %s\n", t, e.cycle, names);
        break;
      }
      if (e.link.kind == ecat::LinkEventKind::recovered && e.link.found[1] != 0) {
        // As bring-up says it: the drive came back with another mapping, which the recovery wrote.
        (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": link recovered: %s (first seen in cycle %" PRIu64
                          "); PDO mapping rewritten (it differed from the plan): %" PRIu32 " SDO writes\n",
                          t, e.cycle, names, e.link.detected_cycle, e.link.found[1]);
        break;
      }
      (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": link %s: %s (first seen in cycle %" PRIu64 ")\n", t,
                        e.cycle, ecat::to_string(e.link.kind), names, e.link.detected_cycle);
      break;
    case HandlerEventKind::ring_report: {
      char line[256];
      (void)ecat::describe(e.ring, drivers::kRobotNetworkPlan, line, sizeof line);
      (void)std::printf("[%8.3f s] ethercat: %s\n", t, line);
      break;
    }
    case HandlerEventKind::loss_reported:
      (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64
                        ": step 1: cannot reach %s; excluded from commands, reported to the joint manager\n",
                        t, e.cycle, names);
      break;
    case HandlerEventKind::loss_recorded:
      (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64
                        ": step 6: joint manager answered (error-joints file: %s); resuming with the other joints\n",
                        t, e.cycle, e.file_status == Errc::ok ? "written" : to_string(e.file_status));
      break;
    case HandlerEventKind::safe_stop:
      (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": SAFE STOP: %s over its limit (%s: %g, limit %g); every drive disabled, worm gears holding\n",
                        t, e.cycle, e.stop.first_joint < kJointCount ? kJoints[e.stop.first_joint].name : "?",
                        to_string(e.stop.first.reason), e.stop.first.value, e.stop.first.limit);
      break;
    case HandlerEventKind::waiting_for_op: {
      const std::uint8_t first = drivers::first_slave(e.link.slaves);
      const bool read = e.link.al_status != 0;
      (void)std::printf("[%8.3f s] ethercat: not in OP yet (%.1f s after SAFE-OP): %d slave(s) not in OP; first %s: %s%s,"
                        " AL status code 0x%04X %s; still trying\n",
                        t, seconds(e.link.time), ecat::popcount(e.link.slaves), drivers::slave_end_name(first),
                        read ? ecat::reg::to_string(static_cast<ecat::reg::AlState>(e.link.al_status & ecat::reg::kAlStateMask)) : "not read yet",
                        (e.link.al_status & ecat::reg::kAlErrorBit) != 0 ? " with error" : "",
                        e.link.al_status_code, ecat::reg::explain_al_status_code(e.link.al_status_code));
      break;
    }
    case HandlerEventKind::drives_disabled:
      (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": every reachable drive disabled\n", t, e.cycle);
      break;
  }
}

const char* rc_task_name(std::size_t task) noexcept { return task == 0 ? "rc-rescue" : "rc-teleop"; }

struct HandlerSideLog {
  bool scenario_failure_announced{false};
  bool op_announced{false};
};
HandlerSideLog g_handler_log;

}  // namespace

void print_joint_events(JointEventQueue& events, JointEventPrinter& printer) noexcept {
  static std::uint64_t dropped_reported = 0;
  JointEvent e{};
  while (events.pop(e)) printer.print(e);
  const std::uint64_t dropped = events.dropped();
  if (dropped != dropped_reported) {
    (void)std::printf("joint-manager: event queue full: %" PRIu64 " event(s) not printed (%" PRIu64 " in all)\n",
                      dropped - dropped_reported, dropped);
    dropped_reported = dropped;
  }
}

MotionSnapshot read_motion() noexcept {
  MotionSnapshot snap;
  snap.owner_word = shared_links().motion.owner.word();
  for (std::size_t k = 0; k < kRcTasksRun; ++k) snap.read[k] = shared_links().motion.task_state[k].try_read(snap.state[k]);
  return snap;
}

void print_motion_changes(MotionLog& log, const MotionSnapshot& snap, hal::Nanoseconds at) noexcept {
  const std::uint64_t word = snap.owner_word;
  if (word != log.owner_word) {
    log.owner_word = word;
    const std::uint8_t task = MotionOwner::task_of(word);
    if (task == kNoOwnerTask) {
      (void)std::printf("[%8.3f s] motion: no owner (generation %" PRIu64 "): every enabled joint holds its reference%s\n",
                        seconds(at), MotionOwner::generation_of(word),
                        MotionOwner::held_for_operator(word) ? "; held for the operator (ctl owner N)" : "");
    } else {
      (void)std::printf("[%8.3f s] motion: owned by %s (RC task %u, generation %" PRIu64 ")\n", seconds(at),
                        task < kRcTasksRun ? rc_task_name(task) : "?", static_cast<unsigned>(task),
                        MotionOwner::generation_of(word));
    }
  }
  for (std::size_t k = 0; k < kRcTasksRun; ++k) {
    const RcTaskState& now = snap.state[k];
    if (!snap.read[k] || now.periods == 0) continue;
    const RcTaskState& before = log.last[k];
    const auto mode = static_cast<RcMode>(now.mode);
    if (!log.seen[k] || now.mode != before.mode || (mode == RcMode::rescue_motion && now.phase != before.phase)) {
      if (mode == RcMode::rescue_motion) {
        (void)std::printf("[%8.3f s] %s: rescue motion: %s\n", seconds(at), rc_task_name(k),
                          kin::to_string(static_cast<kin::RescuePhase>(now.phase)));
        if (now.phase > log.rescue_phase_reached) log.rescue_phase_reached = now.phase;
      } else {
        (void)std::printf("[%8.3f s] %s: %s\n", seconds(at), rc_task_name(k), to_string(mode));
      }
    }
    if (log.seen[k] && now.owns && now.out_of_service != before.out_of_service) {
      char names[kJointNamesCapacity];
      format_joint_names(now.out_of_service, names, sizeof names);
      (void)std::printf("[%8.3f s] %s: joints out of service: %s; locked, the motion goes on with the others\n",
                        seconds(at), rc_task_name(k), names);
    }
    log.last[k] = now;
    log.seen[k] = true;
  }
}

void print_local_replies(hal::Nanoseconds at) noexcept {
  ControlReply reply;
  while (shared_links().local_replies.try_pop(reply)) {
    // The text is read at most to its array's end: a damaged segment's reply need not hold its NUL.
    (void)std::printf("[%8.3f s] operator: %s: %s%s%.*s\n", seconds(at), protocol::to_string(reply.request_type),
                      reply.outcome == protocol::Outcome::accepted ? "accepted" : "refused: ",
                      reply.outcome == protocol::Outcome::accepted && reply.text[0] != '\0' ? "; " : "",
                      static_cast<int>(reply.text.size()), reply.text.data());
  }
}

Status finish_capture(const char* path) noexcept {
  while (g_run.capture_queue.drain(g_run.capture, kCaptureFramesPerLoggerPass) != 0) {
  }
  const ecat::CaptureQueueStats queued = g_run.capture_queue.stats();
  (void)std::printf("rescue-motion run: capture %s: %" PRIu64 " frames, %" PRIu64 " write errors, %" PRIu64
                    " dropped (queue full)\n",
                    path, g_run.capture.stats().frames_written, g_run.capture.stats().write_errors, queued.frames_dropped);
  return g_run.capture.close();
}

void report_if_never_in_op() noexcept {
  if (run_control().op.load(std::memory_order_acquire) || g_run.tasks.handler == nullptr) return;
  ecat::Master& master = g_run.tasks.handler->bus().master();
  const ecat::BringUpReport& r = master.report();
  (void)std::printf("rescue-motion run: the network never reached OP\n");
  if (r.failed_step != nullptr) {  // the master's OP limit passed: its whole report
    ecat::print_bring_up_failure(stdout, "rescue-motion run: ", "rescue-motion run: ", master);
  } else if (r.al_failure.position != ecat::kNoPosition) {  // a slave refused OP before that limit
    char line[256];
    (void)ecat::describe(r.al_failure, master.plan(), line, sizeof line);
    (void)std::printf("rescue-motion run: %s\n", line);
  }
}

void handler_side_pass() noexcept {
  RunControl& state = run_control();
  const FirmwareOptions& options = *g_run.tasks.options;
  const ScenarioRunner& scenario = *g_run.tasks.scenario;
  // The scenario's cut is announced by the operator's side (with the motion it causes); a failed
  // action's reason is the handler's own.
  if (!g_handler_log.scenario_failure_announced && state.scenario_acted.load(std::memory_order_acquire) &&
      !scenario.action_status().ok()) {
    g_handler_log.scenario_failure_announced = true;
    (void)std::printf("scenario %s: %s\n", options.scenario.name, scenario.action_status().error().what);
  }
  HandlerEvent event{};
  while (g_run.tasks.handler->pop_event(event)) print_handler_event(event, g_run.tasks.start);
  if (!g_handler_log.op_announced && state.op.load(std::memory_order_acquire)) {
    g_handler_log.op_announced = true;
    (void)std::printf("[%8.3f s] ethercat: network in OP, cycling every 1 ms\n",
                      seconds(state.op_at.load(std::memory_order_relaxed) - g_run.tasks.start));
  }
  if (g_run.capture.is_open()) (void)g_run.capture_queue.drain(g_run.capture, kCaptureFramesPerLoggerPass);
}

void manager_side_pass() noexcept { print_joint_events(*g_run.tasks.joint_events, *g_run.tasks.joint_event_printer); }

}  // namespace rescue::app::runner
