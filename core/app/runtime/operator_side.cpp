// The operator's side of the run (operator_side.hpp).
#include "core/app/runtime/operator_side.hpp"

#include <cstdio>

#include "core/app/runtime/liveness_watch.hpp"
#include "core/app/runtime/repeat_limiter.hpp"
#include "core/app/runtime/run_context.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app::runner {
namespace {

bool send_local(protocol::MessageType type, JointMask joints) noexcept {
  ControlRequest request;
  request.type = type;
  request.joints = joints;
  if (shared_links().local_requests.try_push(request)) return true;
  run_control().dropped[static_cast<std::size_t>(DropCounter::local_requests_dropped)].fetch_add(1, std::memory_order_relaxed);
  (void)std::printf("operator: request queue full, %s dropped\n", protocol::to_string(type));
  return false;
}

// Whether the handler's latest published values show every joint of `joints` reachable.
bool all_reachable(JointMask joints) noexcept {
  RobotSample sample{};
  if (!shared_links().samples.try_read(sample)) return false;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) != 0 && !sample[j].reachable) return false;
  }
  return true;
}

// The scenario's cut, from the handler's words in the segment (its process or thread).
void announce_scenario(OperatorSide& side) noexcept {
  const RunControl& state = run_control();
  if (side.scenario_announced || !state.scenario_acted.load(std::memory_order_acquire)) return;
  side.scenario_announced = true;
  if (!state.scenario_ok.load(std::memory_order_relaxed)) return;  // the handler's side says why
  const Scenario& wanted = g_run.tasks.options->scenario;
  char names[kJointNamesCapacity];
  format_joint_names(wanted.expected_lost, names, sizeof names);
  (void)std::printf("[%8.3f s] scenario %s: %s %s (expect %s lost)\n",
                    seconds(state.scenario_at.load(std::memory_order_relaxed) - g_run.tasks.start), wanted.name,
                    wanted.kind == ScenarioKind::power_cycle    ? "power-cycle the drive of"
                    : wanted.kind == ScenarioKind::cable_damage ? "damage 5 frames on the cable into"
                                                                : "cut the link into",
                    kJoints[wanted.cut_joint].name, names);
}

// The real-time tasks the liveness watch reports (their heartbeats, TaskLinks::task_heartbeat_ns).
constexpr std::uint32_t kWatchedTasks = (1U << static_cast<unsigned>(StatTask::ethercat_handler)) |
                                        (1U << static_cast<unsigned>(StatTask::joint_manager)) |
                                        (1U << static_cast<unsigned>(StatTask::rc_rescue)) |
                                        (1U << static_cast<unsigned>(StatTask::rc_teleop));
const char* const kWatchedNames[kTaskStatSlots] = {"ethercat-handler", "joint-manager", "socket-handler",
                                                   "message-parser",   "rc-rescue",     "rc-teleop"};

// What a silent task means for the robot, and what the firmware does about it (docs/tasks.md
// "Liveness").
const char* consequence_of_silence(std::size_t task) noexcept {
  switch (static_cast<StatTask>(task)) {
    case StatTask::ethercat_handler:
      return "no frame reaches the drives: after 100 ms without one their SyncManager watchdog disables their outputs "
             "and the worm gears hold the joints; `ctl status`, `slaves`, `master` mark the handler's figures stale; "
             "nothing else may send frames, so the supervisor waits for it (its death ends the run)";
    case StatTask::joint_manager:
      return "the EtherCAT handler keeps every drive on its last demand and still stops the robot on any limit; no "
             "operator command is applied and no loss is recorded until it runs again; the supervisor waits for it "
             "(its death ends the run)";
    default:
      return "if it owns the motion, the EtherCAT handler holds its joints and releases the owner after 50 ms; the "
             "supervisor waits for it (a dead RC task is restarted)";
  }
}

// The supervisor's liveness watch (the logging thread under --threads): one check per pass.
LivenessWatch& liveness_watch() noexcept {
  static LivenessWatch watch(g_run.tasks.options->task_silent_after, kWatchedTasks);
  return watch;
}

void liveness_pass(hal::Nanoseconds now) noexcept {
  LivenessWatch& watch = liveness_watch();
  static RepeatLimiter<kTaskStatSlots> limiter(config::kSilenceReportIntervalNs);
  static std::array<bool, kTaskStatSlots> shown{};  // whether each task's latest silence was printed
  std::array<LivenessChange, kTaskStatSlots> changes{};
  const std::size_t n = watch.check(now, shared_links().task_heartbeat_ns, changes);
  RunControl& state = run_control();
  for (std::size_t i = 0; i < n; ++i) {
    const LivenessChange& c = changes[i];
    const double at = seconds(now - g_run.tasks.start);
    if (c.kind == LivenessChange::Kind::silent) {
      // Repeats rate-limited: the first line whole, then at most one per interval, with the count left out.
      const RepeatLimiter<kTaskStatSlots>::Decision line = limiter.admit(c.task, now);
      shown[c.task] = line.print;
      if (line.print) {
        (void)std::printf("[%8.3f s] supervisor: %s has completed no period for %.1f ms (silent after %.1f ms)", at,
                          kWatchedNames[c.task], static_cast<double>(c.silent_ns) / 1e6,
                          static_cast<double>(watch.silent_after()) / 1e6);
        if (line.suppressed > 0) {
          (void)std::printf("; %llu silences of it left out since its last line (one line per %.0f s at most)",
                            static_cast<unsigned long long>(line.suppressed), static_cast<double>(limiter.interval()) / 1e9);
        }
        (void)std::printf(": %s\n", line.first ? consequence_of_silence(c.task) : "what it means: its first line");
      }
      state.silent_tasks.fetch_or(1U << c.task, std::memory_order_relaxed);
      state.silences_reported.fetch_add(1, std::memory_order_relaxed);
      if (c.silent_ns > state.silence_report_age_max_ns.load(std::memory_order_relaxed)) {
        state.silence_report_age_max_ns.store(c.silent_ns, std::memory_order_relaxed);
      }
    } else {
      const bool past_watchdog = c.task == static_cast<std::size_t>(StatTask::ethercat_handler) && c.silent_ns >= config::kDriveWatchdogNs;
      state.silent_tasks.fetch_and(~(1U << c.task), std::memory_order_relaxed);
      // A silence left out leaves out its end, unless the drives were disabled meanwhile: that always shows.
      if (!shown[c.task] && !past_watchdog) continue;
      (void)std::printf("[%8.3f s] supervisor: %s runs again after %.1f ms without a period%s\n", at, kWatchedNames[c.task],
                        static_cast<double>(c.silent_ns) / 1e6,
                        past_watchdog ? ": longer than the drives' watchdog; the handler re-arms them to OP and enables "
                                        "them again, each holding its actual position; a Motion owner is released, so "
                                        "the robot moves again only when the operator says (ctl owner N; docs/tasks.md "
                                        "\"Liveness\")"
                                      : "");
    }
  }
}

}  // namespace

std::uint64_t liveness_damaged_beats() noexcept {
  return g_run.tasks.options != nullptr ? liveness_watch().damaged_beats() : 0;
}

void operator_side_pass(OperatorSide& side) noexcept {
  hal::Clock& clock = *g_run.tasks.clock;
  const MotionSnapshot motion = read_motion();
  liveness_pass(clock.now());
  announce_scenario(side);
  const bool op = run_control().op.load(std::memory_order_acquire);
  // The DFA takes its steps only for reachable joints: wait until the handler's published values
  // show every joint that is not recorded lost reachable (the first OP cycles may not).
  if (op && !side.clear_sent && all_reachable(side.to_clear)) {
    side.clear_sent = true;
    char names[kJointNamesCapacity];
    format_joint_names(side.to_clear, names, sizeof names);
    (void)std::printf("[%8.3f s] operator: clear repaired joints %s (then reset)\n", seconds(clock.now() - g_run.tasks.start), names);
    (void)send_local(protocol::MessageType::clear_joints, side.to_clear);
  }
  if (op && side.clear_sent && !side.initialized && all_reachable(kAllJoints & ~side.out_of_service)) {
    side.initialized = true;
    (void)std::printf("[%8.3f s] operator: initialize robot (select mode, set reference, enable)\n",
                      seconds(clock.now() - g_run.tasks.start));
    (void)send_local(protocol::MessageType::initialize, kAllJoints & ~side.out_of_service);
    if (g_run.tasks.options->scenario.rescue_motion) {
      // After the initialize (the parser takes one request at a time): the rescue RC task takes the motion.
      (void)std::printf("[%8.3f s] operator: owner %u (the rescue RC task takes the motion)\n",
                        seconds(clock.now() - g_run.tasks.start), static_cast<unsigned>(RcTaskId::rescue));
      ControlRequest take;
      take.type = protocol::MessageType::take_owner;
      take.task = static_cast<std::uint8_t>(RcTaskId::rescue);
      if (!shared_links().local_requests.try_push(take)) {
        run_control().dropped[static_cast<std::size_t>(DropCounter::local_requests_dropped)].fetch_add(1, std::memory_order_relaxed);
        (void)std::printf("operator: request queue full, owner dropped\n");
      }
    }
  }
  print_local_replies(clock.now() - g_run.tasks.start);
  print_motion_changes(side.motion, motion, clock.now() - g_run.tasks.start);
  (void)std::fflush(stdout);
}

void disable_enabled_joints() noexcept {
  RobotDemand demand{};
  JointMask enabled = 0;
  if (shared_links().demand.try_read(demand)) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if (demand[j].enable) enabled |= joint_bit(j);
    }
  }
  if (enabled == 0 || !send_local(protocol::MessageType::disable, enabled)) return;
  hal::MonotonicClock wait_clock;
  const hal::Nanoseconds give_up = wait_clock.now() + MessageParser::kReplyTimeout + 100 * hal::kNsPerMs;
  while (shared_links().local_replies.empty_approx() && wait_clock.now() < give_up) {
    wait_clock.sleep_until(wait_clock.now() + hal::kNsPerMs);
  }
  print_local_replies(g_run.tasks.clock->now() - g_run.tasks.start);
}

}  // namespace rescue::app::runner
