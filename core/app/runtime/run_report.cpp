// The end of a run (run_report.hpp), and exit_status_for (firmware.hpp).
#include "core/app/runtime/run_report.hpp"

#include <cinttypes>
#include <cstdio>

#include "core/app/config/command_line.hpp"
#include "core/app/config/firmware_config.hpp"
#include "core/app/runtime/run_context.hpp"
#include "core/app/runtime/segment_records_report.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "core/app/runtime/task_cpu.hpp"
#include "core/kinematics/self_collision.hpp"
#include "core/kinematics/task_priority_ik.hpp"
#include "core/memory/heap_guard.hpp"

namespace rescue::app {

int exit_status_for(fsm::RobotCondition condition) noexcept {
  return condition == fsm::RobotCondition::error ? kExitRobotError : 0;
}

}  // namespace rescue::app

namespace rescue::app::runner {
namespace {

// `run --scenario rescue`: an arm with every joint in service ends this close to its target.
constexpr double kRescueResidualM = 0.005;
constexpr double kRescueResidualRad = 0.02;
// After damage the motion stays right (docs/kinematics.md "After damage"): a whole arm's palm is
// commanded within these of its path (no arm damaged, and the healthy arm after a loss), the waist
// moves at most this after the loss, and a damaged arm's palm at most its stopping budget (the rescue
// task keeps each palm slow enough for it, config::kDamagedPalmStopBudgetM).
constexpr double kPathDeviationWholeM = 0.001;
constexpr double kPathDeviationAfterLossM = 0.005;
constexpr double kWaistTravelAfterLossRad = 0.01;

// "n/a" for a figure that does not apply, else the value.
void print_figure(const char* key, bool applies, double value, int decimals) noexcept {
  if (applies) {
    (void)std::printf("%s: %.*f\n", key, decimals, value);
  } else {
    (void)std::printf("%s: n/a\n", key);
  }
}

// The rescue motion's path and damage figures within their bounds (nullptr: yes; else what is not).
const char* rescue_motion_fault(const RcTaskState& rescue) noexcept {
  for (int arm = 0; arm < 2; ++arm) {
    if (!rescue.path_measured[arm]) continue;
    const bool healthy_after_loss = rescue.loss_seen && (rescue.damaged_arms & (1U << arm)) == 0;
    const double bound = healthy_after_loss ? kPathDeviationAfterLossM : kPathDeviationWholeM;
    if (rescue.path_deviation_m[arm] > bound) return "a palm was commanded off its path";
  }
  if (rescue.loss_seen && rescue.waist_travel_after_loss_rad > kWaistTravelAfterLossRad) {
    return "the waist moved after an arm was damaged";
  }
  for (int arm = 0; arm < 2; ++arm) {
    if ((rescue.damaged_arms & (1U << arm)) != 0 && rescue.palm_travel_after_loss_m[arm] > config::kDamagedPalmStopBudgetM) {
      return "a damaged arm's palm travelled beyond its stopping budget";
    }
  }
  if (!rescue.margin_measured) return "no support margin was measured";
  if (rescue.collision_stop) return "the motion stopped to avoid a self-collision";
  return nullptr;
}

// Every reference the rescue RC task drove within each joint's speed and acceleration limits.
bool rescue_within_limits(const RcTaskState& rescue) noexcept {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (rescue.max_speed_rad_s[j] > kJoints[j].limits.velocity_max_rad_s * (1.0 + 1e-9)) return false;
    if (rescue.max_acceleration_rad_s2[j] > kin::kJointAcceleration[j] * (1.0 + 1e-6)) return false;
  }
  return true;
}

// The one line saying where a signal stopped the run.
void print_stop_line(const RunControl& state, bool drives_disabled, bool file_dirty) noexcept {
  (void)std::printf("rescue-motion run: stopped by signal %d %s, after %" PRIu64 " cycles; drives %s; error-joints "
                    "file %s\n",
                    stop_signal(), state.op.load() ? "while in OP" : "before OP (going to OP)", state.cycles.load(),
                    drives_disabled ? "disabled" : "told to disable (not all confirmed)",
                    file_dirty ? "NOT written" : "up to date");
}

const char* const kTaskNames[kTaskStatSlots] = {"ethercat-handler", "joint-manager", "socket-handler",
                                                "message-parser",   "rc-rescue",     "rc-teleop"};

// `key: value` lines: per task (process), heap allocations and page faults after its init.
void print_task_health(bool operator_port) noexcept {
  for (std::size_t i = 0; i < kTaskStatSlots; ++i) {
    if (!operator_port && static_cast<StatTask>(i) == StatTask::socket_handler) continue;
    const TaskHealth& h = run_control().health[i];
    if (!h.reported.load(std::memory_order_acquire)) {
      (void)std::printf("%s heap allocations after init: unknown (it did not report)\n", kTaskNames[i]);
      continue;
    }
    (void)std::printf("%s heap allocations after init: %" PRIu64 "\n", kTaskNames[i], h.heap_allocations.load());
    (void)std::printf("%s page faults after init: %" PRIu64 "\n", kTaskNames[i], h.page_faults.load());
    (void)std::printf("%s restarts: %u\n", kTaskNames[i], h.restarts.load());
    TaskStat stat{};
    if (shared_links().task_stats[i].try_read(stat)) {
      (void)std::printf("%s periods: %" PRIu64 "\n", kTaskNames[i], stat.periods);
      (void)std::printf("%s periods missed: %" PRIu64 "\n", kTaskNames[i], stat.missed);
      (void)std::printf("%s max execution time: %" PRIu64 " ns\n", kTaskNames[i], stat.max_execution_ns);
    }
  }
}

}  // namespace

std::uint64_t print_run_figures(const FirmwareOptions& options, const SocketHandler& socket) noexcept {
  RunControl& state = run_control();
  const bool operator_port = g_run.tasks.operator_port;
  const HeapGuardCounters heap = heap_guard_counters();
  const JointMask lost = state.lost_joints.load();
  // Healthy: never marked lost in this run (a joint lost, then cleared, missed its cycles while lost).
  const JointMask ever_lost = lost | state.lost_since_start.load();
  const auto condition = static_cast<fsm::RobotCondition>(state.condition.load());
  std::uint64_t healthy_missed = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((ever_lost & joint_bit(j)) == 0) healthy_missed += state.missed_cycles[j].load();
  }
  char lost_names[kJointNamesCapacity];
  format_joint_names(lost, lost_names, sizeof lost_names);
  if (stop_signal() != 0) print_stop_line(state, state.drives_disabled.load(), state.file_dirty.load());
  if (!state.handler_done.load()) {
    (void)std::printf("rescue-motion run: the EtherCAT handler did not report its final figures: the ones below are "
                      "its last published\n");
  }
  const bool manager_reported = state.manager_done.load(std::memory_order_acquire);
  (void)std::printf("rescue-motion run: %" PRIu64 " cycles; healthy joints missed %" PRIu64
                    " cycles; frames late or lost: %" PRIu64 "; late periods: %" PRIu64 " (%" PRIu64
                    " not run); lost joints: %s; robot %s\n",
                    state.cycles.load(), healthy_missed, state.frames_missing.load(), state.late_periods.load(),
                    state.skipped_periods.load(), manager_reported ? lost_names : "unknown", manager_reported ? fsm::to_string(condition) : "unknown (the joint manager did not report)");
  if (manager_reported && (ever_lost & ~lost) != 0) {
    char cleared[kJointNamesCapacity];
    format_joint_names(ever_lost & ~lost, cleared, sizeof cleared);
    (void)std::printf("rescue-motion run: lost, then cleared during the run: %s\n", cleared);
  }
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::uint64_t m = (ever_lost & joint_bit(j)) != 0 ? 0 : state.missed_cycles[j].load();
    if (m == 0) continue;
    const bool placed_late = (options.scenario.may_miss_first_frame & joint_bit(j)) != 0 && m <= 1;
    (void)std::printf("rescue-motion run: %s missed %" PRIu64 " cycles%s\n", kJoints[j].name, m,
                      placed_late ? " (behind the power-cycled drive: the frame that first showed the shortfall "
                                    "could not tell it from a cut)"
                                  : "");
  }
  (void)std::printf("rescue-motion run: heap allocations after init: %" PRIu64 "\n", heap.allocations);
  (void)std::printf("rescue-motion run: queues:");
  for (std::size_t i = 0; i < kDropCounters; ++i) (void)std::printf(" %s %" PRIu64, kDropCounterNames[i], state.dropped[i].load());
  (void)std::printf("\n");
  print_task_health(operator_port);
  SocketCounters counted{};
  (void)shared_links().socket_counters.try_read(counted);
  if (operator_port) {
    (void)std::printf("rescue-motion run: datagrams %" PRIu64 ", accepted %" PRIu64, counted.datagrams, counted.accepted);
    for (std::size_t i = 0; i < protocol::kRejectionCount; ++i) {
      (void)std::printf(", %s %" PRIu64, protocol::to_string(static_cast<protocol::Rejection>(i)), counted.rejected[i]);
    }
    (void)std::printf("\n");
    (void)std::printf("rescue-motion run: socket handler wake-ups %" PRIu64 ", at the budget %" PRIu64
                      ", most datagrams in one wake-up %" PRIu64 " (budget %zu)\n",
                      counted.wakeups, counted.budget_exhausted, state.socket_max_per_wakeup.load(), SocketHandler::kBudget);
  }
  if (options.report != nullptr) {
    options.report->cycles = state.cycles.load();
    options.report->healthy_missed = healthy_missed;
    options.report->frames_missing = state.frames_missing.load();
    options.report->datagrams = counted.datagrams;
    options.report->accepted = counted.accepted;
    options.report->rejected = counted.rejected;
    options.report->control_port = socket.control_port();
    options.report->sensor_port = socket.sensor_port();
  }
  return healthy_missed;
}

JointMask joints_ended_in_error(const RobotJointStatus& ended, JointMask excused) noexcept {
  JointMask faulted = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((excused & joint_bit(j)) == 0 && ended[j].state == fsm::JointState::error) faulted |= joint_bit(j);
  }
  return faulted;
}

int scenario_verdict(const Scenario& wanted, const RunControl& state, JointMask lost, JointMask restored,
                     bool auto_clear_power_cycled, std::uint8_t rescue_phase_reached) noexcept {
  if (wanted.kind == ScenarioKind::none) return 0;
  if (!state.scenario_acted.load() || !state.scenario_ok.load()) return fail("run", "the scenario's link cut did not happen");
  // Marked lost at any time of the run: a joint cleared since (by the operator or automatically) was lost too.
  const JointMask ever_lost = lost | state.lost_since_start.load();
  if ((ever_lost & wanted.expected_lost) != wanted.expected_lost ||
      (ever_lost & ~(wanted.expected_lost | restored)) != 0) {
    return fail("run", "the joints marked lost differ from the joints behind the cut");
  }
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((ever_lost & joint_bit(j)) != 0) continue;
    const std::uint64_t allowed = (wanted.may_miss_first_frame & joint_bit(j)) != 0 ? 1U : 0U;
    if (state.missed_cycles[j].load() > allowed) return fail("run", "healthy joints missed cycles during the link cut");
  }
  // A joint outside the cut (and not restored in Error from the file) must end where the scenario
  // left it: a drive fault or a limit on a healthy joint fails the scenario, whatever else held.
  RobotJointStatus ended{};
  if (!shared_links().joint_status.try_read(ended)) return fail("run", "the joint manager's status could not be read");
  const JointMask faulted = joints_ended_in_error(ended, ever_lost | restored);
  if (faulted != 0) {
    char names[kJointNamesCapacity];
    format_joint_names(faulted, names, sizeof names);
    std::size_t first_joint = 0;
    while ((faulted & joint_bit(first_joint)) == 0) ++first_joint;
    const FaultReason first = ended[first_joint].fault;
    char text[kJointNamesCapacity + 96];
    (void)std::snprintf(text, sizeof text, "joints outside the cut ended in Error: %s (%s)", names, to_string(first));
    return fail("run", text);
  }
  if (wanted.kind == ScenarioKind::power_cycle && auto_clear_power_cycled && (lost & wanted.expected_lost) != 0) {
    return fail("run", "the power-cycled joint was not cleared automatically (--auto-clear-power-cycled)");
  }
  if (state.file_dirty.load()) return fail("run", "the error-joints file could not be written");
  if (wanted.rescue_motion) {
    if (state.intake_used_periods.load() == 0) return fail("run", "the rescue RC task's references never drove the joints");
    if (rescue_phase_reached != static_cast<std::uint8_t>(kin::RescuePhase::done)) {
      return fail("run", "the rescue motion did not reach its end before the stop");
    }
    RcTaskState rescue{};
    if (!shared_links().motion.task_state[static_cast<std::size_t>(RcTaskId::rescue)].try_read(rescue)) {
      return fail("run", "the rescue RC task's figures could not be read");
    }
    if (!rescue_within_limits(rescue)) return fail("run", "a rescue reference exceeded a joint's speed or acceleration limit");
    // An arm with every joint in service ends on its target; a lost arm's residual is only reported.
    for (int arm = 0; arm < 2; ++arm) {
      if ((rescue.out_of_service & joints_of_branch(arm == 0 ? Branch::left_arm : Branch::right_arm)) != 0) continue;
      if (rescue.position_residual_m[arm] > kRescueResidualM || rescue.rotation_residual_rad[arm] > kRescueResidualRad) {
        return fail("run", "an arm with every joint in service did not reach its target");
      }
    }
    if (!(rescue.min_support_margin_m > 0.0)) return fail("run", "the centre of mass left the support polygon");
    const char* motion_fault = rescue_motion_fault(rescue);
    if (motion_fault != nullptr) return fail("run", motion_fault);
  }
  return 0;
}

void print_run_summary(const RunSummary& s) noexcept {
  (void)std::printf("clock: wall (CLOCK_MONOTONIC); tasks: %s\n",
                    s.processes ? "processes under a supervisor" : "threads of one process");
  (void)std::printf("periods_run: %" PRIu64 "\n", s.cycles);
  // Time to OP, from the run's clock origin (the NIC opened), as "network in OP" says it.
  if (s.bring_up != nullptr) {
    (void)std::printf("bring_up_to_safe_op_ms: %.1f\n", static_cast<double>(s.bring_up->safe_op_at - s.start) / 1e6);
    const hal::Nanoseconds op_at = run_control().op.load() ? run_control().op_at.load() : -1;
    if (op_at >= 0) (void)std::printf("bring_up_to_op_ms: %.1f\n", static_cast<double>(op_at - s.start) / 1e6);
    (void)std::printf("bring_up_sii_cache_hits: %" PRIu32 " of %u slaves\n", s.bring_up->sii.cache_hits,
                      static_cast<unsigned>(s.bring_up->slaves_counted));
  }
  for (std::size_t k = 0; k < kTaskStatSlots; ++k) {
    TaskStat stat{};
    if (!shared_links().task_stats[k].try_read(stat) || stat.name[0] == '\0') continue;
    char key[protocol::kNameSize + 1];
    std::size_t n = 0;
    for (; n < protocol::kNameSize && stat.name[n] != '\0'; ++n) key[n] = stat.name[n] == '-' ? '_' : stat.name[n];
    key[n] = '\0';
    const TaskHealth& health = shared_links().run.health[k];
    (void)std::printf("periods_run_%s: %" PRIu64 "\n", key, stat.periods);
    (void)std::printf("periods_missed_%s: %" PRIu64 "\n", key, stat.missed);
    (void)std::printf("max_execution_ns_%s: %" PRIu64 "\n", key, stat.max_execution_ns);
    (void)std::printf("page_faults_%s: %" PRIu64 "\n", key, health.page_faults.load());
  }
  (void)std::printf("heap_allocations_after_init: %" PRIu64 "\n", s.heap_allocations);
  // Every task's CPU per second of wall time, idle and moving (runtime/task_cpu.hpp).
  (void)std::fflush(stdout);
  run_task_cpu().print(stdout);
  // The supervisor's liveness watch (docs/tasks.md "Liveness"): real-time tasks reported silent, and
  // the largest heartbeat age at such a report (the limit plus the supervisor's own delay).
  (void)std::printf("task_silences_reported: %" PRIu64 "\n", shared_links().run.silences_reported.load());
  (void)std::printf("task_silence_report_age_max_ms: %.3f\n",
                    static_cast<double>(shared_links().run.silence_report_age_max_ns.load()) / 1e6);
  // The queues between the tasks: what each dropped (or deferred), run_control.hpp's DropCounter.
  for (std::size_t i = 0; i < kDropCounters; ++i) {
    (void)std::printf("%s: %" PRIu64 "\n", kDropCounterNames[i], shared_links().run.dropped[i].load(std::memory_order_relaxed));
  }
  // Records of the segment each task refused as damaged (docs/shared-memory.md).
  print_segment_records_refused(stdout, shared_links().run, s.supervisor_damaged_beats, s.socket != nullptr);
  char names[kJointNamesCapacity];
  format_joint_names(s.lost, names, sizeof names);
  std::size_t lost_count = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) lost_count += (s.lost & joint_bit(j)) != 0 ? 1U : 0U;
  (void)std::printf("joints_lost: %zu\n", lost_count);
  (void)std::printf("joints_lost_names: %s\n", names);
  for (std::size_t i = 0; i < protocol::kRejectionCount; ++i) {
    (void)std::printf("datagrams_rejected_%s: %" PRIu64 "\n", protocol::to_string(static_cast<protocol::Rejection>(i)),
                      s.socket != nullptr ? s.socket->rejected[i] : 0U);
  }
  (void)std::printf("owner_periods: %" PRIu64 "\n", s.intake.owned_periods);
  (void)std::printf("owner_references_used: %" PRIu64 "\n", s.intake.used_periods);
  (void)std::printf("owner_misses: %" PRIu64 "\n", s.intake.misses);
  (void)std::printf("owner_releases: %" PRIu64 "\n", s.intake.releases);
  (void)std::printf("rescue_phase_reached: %s\n", kin::to_string(static_cast<kin::RescuePhase>(s.rescue_phase_reached)));
  RcTaskState rescue{};
  if (shared_links().motion.task_state[static_cast<std::size_t>(RcTaskId::rescue)].try_read(rescue)) {
    // The palms' distance from their targets at the references sent (n/a: the palm left the task
    // when its arm was damaged).
    const bool left_in_task = (rescue.damaged_arms & 1U) == 0;
    const bool right_in_task = (rescue.damaged_arms & 2U) == 0;
    print_figure("rescue_residual_left_m", left_in_task, rescue.position_residual_m[0], 5);
    print_figure("rescue_residual_right_m", right_in_task, rescue.position_residual_m[1], 5);
    print_figure("rescue_residual_left_rad", left_in_task, rescue.rotation_residual_rad[0], 5);
    print_figure("rescue_residual_right_rad", right_in_task, rescue.rotation_residual_rad[1], 5);
    print_figure("rescue_symmetry_error_rad", rescue.symmetry_measured, rescue.symmetry_error_rad, 6);
    (void)std::printf("rescue_max_abs_waist_rad: %.6f\n", rescue.max_abs_waist_rad);
    print_figure("rescue_min_support_margin_m", rescue.margin_measured, rescue.min_support_margin_m, 4);
    print_figure("rescue_path_deviation_left_m", rescue.path_measured[0], rescue.path_deviation_m[0], 5);
    print_figure("rescue_path_deviation_right_m", rescue.path_measured[1], rescue.path_deviation_m[1], 5);
    print_figure("rescue_waist_travel_after_loss_rad", rescue.loss_seen, rescue.waist_travel_after_loss_rad, 6);
    print_figure("rescue_palm_travel_after_loss_left_m", (rescue.damaged_arms & 1U) != 0,
                 rescue.palm_travel_after_loss_m[0], 5);
    print_figure("rescue_palm_travel_after_loss_right_m", (rescue.damaged_arms & 2U) != 0,
                 rescue.palm_travel_after_loss_m[1], 5);
    print_figure("rescue_min_self_clearance_m", rescue.close_pair_seen, rescue.min_self_clearance_m, 5);
    if (rescue.collision_stop) {
      kin::SelfCollisionReport stop{};
      stop.stop = true;
      stop.closest_pair = rescue.collision_pair;
      stop.closest_distance_m = rescue.collision_distance_m;
      char reason[128];
      (void)std::printf("rescue_self_collision_stop: %s\n", kin::stop_reason(stop, kin::IkSettings{}.clearance, reason, sizeof reason));
    } else {
      (void)std::printf("rescue_self_collision_stop: none\n");
    }
    (void)std::printf("rescue_min_time_scale: %.4f\n", rescue.min_time_scale);
    (void)std::printf("rescue_clipped_periods: %" PRIu64 "\n", rescue.clipped_periods);
    for (std::size_t j = 0; j < kJointCount; ++j) {
      (void)std::printf("rescue_max_speed_rad_s_%s: %.4f (limit %.4g)\n", kJoints[j].name, rescue.max_speed_rad_s[j],
                        kJoints[j].limits.velocity_max_rad_s);
      (void)std::printf("rescue_max_acceleration_rad_s2_%s: %.4f (limit %.4g)\n", kJoints[j].name,
                        rescue.max_acceleration_rad_s2[j], kin::kJointAcceleration[j]);
    }
    (void)std::printf("rescue_joint_limits: %s\n", rescue_within_limits(rescue) ? "within" : "exceeded");
  }
}

namespace {

// The joint and limit sent furthest beyond (or closest to) its limit: ratio of the figure to the limit.
struct WorstSent {
  double ratio{0.0};
  std::size_t joint{0};
  double value{0.0};
  double limit{0.0};
};

WorstSent worst_sent(const std::array<std::atomic<double>, kJointCount>& figures, double (*limit_of)(std::size_t)) noexcept {
  WorstSent worst;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const double limit = limit_of(j);
    if (!(limit > 0.0)) continue;  // no such limit on this joint (jerk)
    const double value = figures[j].load(std::memory_order_relaxed);
    if (value / limit > worst.ratio) worst = {value / limit, j, value, limit};
  }
  return worst;
}

double speed_limit_of(std::size_t j) noexcept { return kJoints[j].limits.velocity_max_rad_s; }
double acceleration_limit_of(std::size_t j) noexcept { return kin::kJointAcceleration[j]; }
double jerk_limit_of(std::size_t j) noexcept { return kin::kJointJerk[j]; }

}  // namespace

int sent_joint_limits_exit(const RunControl& state) noexcept {
  struct Limit {
    const char* name;
    const char* unit;
    WorstSent worst;
    double tolerance;
  };
  const Limit limits[] = {
      {"speed", "rad/s", worst_sent(state.sent_max_speed_rad_s, speed_limit_of), 1e-9},
      {"acceleration", "rad/s^2", worst_sent(state.sent_max_acceleration_rad_s2, acceleration_limit_of), 1e-6},
      {"jerk", "rad/s^3", worst_sent(state.sent_max_jerk_rad_s3, jerk_limit_of), 1e-3}};
  bool within = true;
  for (const Limit& l : limits) {
    // The joint is named only when one moved (a ratio of 0 has none: no hand moved, no jerk).
    (void)std::printf("sent_worst_%s_ratio: %.4f (%s)\n", l.name, l.worst.ratio,
                      l.worst.ratio > 0.0 ? kJoints[l.worst.joint].name : "no joint moved");
    within = within && l.worst.ratio <= 1.0 + l.tolerance;
  }
  (void)std::printf("joint_limits: %s\n", within ? "within" : "exceeded");
  if (within) return 0;
  for (const Limit& l : limits) {
    if (l.worst.ratio <= 1.0 + l.tolerance) continue;
    (void)std::fprintf(stderr, "rescue-motion run: %s was sent beyond its %s limit: %.4g %s (limit %.4g): exit status %d\n",
                       kJoints[l.worst.joint].name, l.name, l.worst.value, l.unit, l.worst.limit, kExitJointLimit);
  }
  return kExitJointLimit;
}

int robot_exit(fsm::RobotCondition condition) noexcept {
  const int status = exit_status_for(condition);
  if (status != 0) {
    (void)std::fprintf(stderr, "rescue-motion run: the robot ended in error (every joint in Error): exit status %d\n",
                       status);
  }
  return status;
}

}  // namespace rescue::app::runner
