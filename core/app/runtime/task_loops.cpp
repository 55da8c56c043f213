// The tasks' period loops (task_loops.hpp): handler_task, joint_manager_task, rc_task, parser_task,
// socket_task, and the entry points that run them on g_run.tasks.
#include "core/app/runtime/task_loops.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdio>

#include "core/app/config/firmware_config.hpp"
#include "core/app/config/task_table.hpp"
#include "core/app/runtime/period_schedule.hpp"
#include "core/app/runtime/run_context.hpp"
#include "core/app/runtime/segment_records_report.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/app/tasks/period_mark.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/memory/heap_guard.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "hal/proc/process_identity.hpp"
#include "hal/rt/rt_setup.hpp"

namespace rescue::app::runner {

// The EtherCAT handler's period (its cycle, then the publication of the master's figures), out of
// line with stable names for callgrind's --toggle-collect: toolchain/wcet/run-instructions.sh counts
// its instructions per period in run as instructions.sh does in bench wcet (the mark dumps them).
__attribute__((noinline)) drivers::JointCycleResult run_handler_cycle(EthercatHandler& handler) noexcept { return handler.cycle(); }
__attribute__((noinline)) void run_handler_publish(EthercatHandler& handler, const drivers::JointCycleResult& result,
                                                   hal::Nanoseconds now, std::uint64_t late_periods) noexcept {
  handler.publish_figures(result, now, late_periods);
  mark_period_end("ethercat_handler");
}

namespace {

// Priorities and CPUs: each task's row of the task table (config/task_table.cpp; numbers in
// config/firmware_config.hpp; a configuration file, config/config_file.hpp, may have moved them
// before the run started), applied by the task itself, in its thread or process.
constexpr hal::Nanoseconds kRcTaskPeriod = config::kRcTaskPeriodNs;
constexpr hal::Nanoseconds kJointManagerPeriod = config::kJointManagerPeriodNs;
constexpr hal::Nanoseconds kParserPeriod = config::kMessageParserPeriodNs;
constexpr int kSocketWaitMs = config::kSocketWaitMs;
constexpr hal::Nanoseconds kRescueSettle = config::kRescueSettleNs;
constexpr hal::Nanoseconds kFileDrainLimit = config::kFileDrainLimitNs;
constexpr hal::Nanoseconds kStorageWorkerPoll = config::kStorageWorkerPollNs;

// The CPU a task asks for, or the machine's last one when it has fewer (announced by the RT report).
int cpu_for(int wanted) noexcept { return table_cpu_on_this_machine(wanted); }

void apply_thread_rt(const char* task, int priority, int cpu) noexcept {
  // Its name on its thread (and its process, when the task is one): ps -eLo comm, top -H, chrt.
  const Status named = hal::name_this_thread(task);
  if (!named.ok()) (void)std::printf("%s: thread not named: %s\n", task, named.error().what);
  if (cpu_for(cpu) != cpu) {
    (void)std::printf("%s: CPU %d is not on this machine (%ld online): running on CPU %d, the last one\n", task, cpu,
                      sysconf(_SC_NPROCESSORS_ONLN), cpu_for(cpu));
  }
  hal::RtConfig rt;
  rt.lock_memory = g_run.task_processes;  // a forked child does not inherit mlockall; threads: done once
  rt.prefault_stack_bytes = hal::kTaskStackPrefaultBytes;  // what toolchain/rt_verify.py checks stacks against
  rt.fifo_priority = priority;
  rt.cpu = cpu_for(cpu);
  rt.timer_slack_ns = config::kTaskTimerSlackNs;             // as cyclictest
  rt.cpu_wakeup_latency_us = config::kCpuWakeupLatencyUs;  // the process's PM QoS request, as cyclictest
  const hal::RtReport report = hal::apply_rt_config(rt);
  if (!report.fully_applied()) {
    (void)std::printf("%s: running degraded, %zu real-time setting(s) refused:\n", task, report.refused_count());
  }
  for (const hal::RtItemReport& item : report.items) {
    if (item.outcome != hal::RtOutcome::refused) continue;
    char line[256];
    (void)hal::RtReport::format_item(item, line, sizeof line);
    (void)std::printf("%s:   %s\n", task, line);
  }
}

// The task's real-time set-up from its row of the task table; its timing slot says what it asked for.
void apply_task_rt(const char* name, TaskId id) noexcept { apply_thread_rt(name, runner_priority(id), task_spec(id).cpu); }
int task_cpu(TaskId id) noexcept { return cpu_for(task_spec(id).cpu); }
int task_priority(TaskId id) noexcept { return runner_priority(id); }

// The EtherCAT handler stops on a signal to its own process or on the supervisor's word.
bool stop_requested(const RunControl& run) noexcept { return stop_signal() != 0 || run.stop.load(std::memory_order_acquire); }

// Heap allocations and page faults of a task after its init (run_control.hpp, TaskHealth): taken
// when the task is past its set-up, reported in its slot at its end.
class TaskHealthProbe {
 public:
  explicit TaskHealthProbe(TaskHealth& slot) noexcept
      : slot_(&slot),
        heap_at_init_(heap_guard_counters().allocations),
        faults_at_init_(hal::page_faults_of_thread()) {
    slot_->pid.store(static_cast<std::int32_t>(::getpid()), std::memory_order_relaxed);
    slot_->reported.store(false, std::memory_order_release);
  }
  void report() noexcept {
    const hal::PageFaults faults = hal::page_faults_of_thread();
    slot_->heap_allocations.store(heap_guard_counters().allocations - heap_at_init_, std::memory_order_relaxed);
    slot_->page_faults.store(faults.minor + faults.major - faults_at_init_.minor - faults_at_init_.major,
                             std::memory_order_relaxed);
    slot_->reported.store(true, std::memory_order_release);
  }

 private:
  TaskHealth* slot_;
  std::uint64_t heap_at_init_;
  hal::PageFaults faults_at_init_;
};

// A task's timing (runtime/task_timing.hpp's TaskRecorder: histograms, late periods, live figures
// for `ctl tasks` in its port `published`) and its page faults since its set-up, recorded when it ends.
class TaskStats {
 public:
  TaskStats(StatTask id, Seqlock<TaskStat>& published, const char* name, int cpu, int priority) noexcept
      : recorder_(&task_timing()[id]) {
    recorder_->start(published, name, cpu, priority, task_timing().ns_per_tick());
  }
  // One period: due at `due_ns`, begun at `woke_ns`, its work between two TSC readings.
  void period(hal::Nanoseconds due_ns, hal::Nanoseconds woke_ns, std::uint64_t tsc_before, std::uint64_t tsc_after,
              hal::Nanoseconds late_after) noexcept {
    recorder_->period(due_ns, woke_ns, tsc_before, tsc_after, late_after);
  }
  // `count` periods that did not run at all (period_schedule.hpp).
  void skipped(std::uint64_t count) noexcept { recorder_->skipped(count); }
  // The last publication, when the task ends (its page faults: TaskHealthProbe).
  void publish() noexcept { recorder_->publish(); }
  std::uint64_t missed() const noexcept { return recorder_->missed(); }

 private:
  TaskRecorder* recorder_;
};

// A task's start, in this order: its real-time set-up from its row of the task table, its timing
// slot, then its count in tasks_started (the run's init is complete once every task is past it).
TaskStats start_task(const char* name, TaskId id, StatTask slot, const TaskLoopPorts& ports) noexcept {
  apply_task_rt(name, id);
  // ctl tasks: this thread's id and this incarnation's start (the socket handler's uptime).
  ports.health->tid.store(hal::own_thread_id(), std::memory_order_relaxed);
  ports.health->started_ns.store(hal::MonotonicClock().now(), std::memory_order_release);
  TaskStats stats(slot, *ports.stats, name, task_cpu(id), task_priority(id));
  ports.run->tasks_started.fetch_add(1, std::memory_order_release);
  return stats;
}

// A periodic task's loop (period_schedule.hpp): missed periods skipped and counted, its heartbeat
// published through its port every period.
template <typename Work>
void run_periods(const std::atomic<bool>& stop, hal::Clock& clock, hal::Nanoseconds period,
                 hal::Nanoseconds late_after, const TaskLoopPorts& ports, TaskStats& stats, Work work) noexcept {
  app::run_periods(stop, clock, task_timing().timer, period, late_after, stats, *ports.heartbeat_ns, work);
}

// A queue's drop counter in the segment (run_control.hpp), written by the task at its producing end:
// what this process's object counted since it last published (a restarted task process adds its own).
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): one writer per entry, the producing task
std::array<std::uint64_t, kDropCounters> g_drops_published{};
void publish_drops(RunControl& run, DropCounter which, std::uint64_t count) noexcept {
  const auto i = static_cast<std::size_t>(which);
  if (count == g_drops_published[i]) return;
  run.dropped[i].fetch_add(count - g_drops_published[i], std::memory_order_relaxed);
  g_drops_published[i] = count;
}

void publish_handler_drops(RunControl& run, EthercatHandler& handler) noexcept {
  const ecat::Master& master = handler.bus().master();
  publish_drops(run, DropCounter::events_dropped, handler.events_dropped());
  publish_drops(run, DropCounter::reports_dropped, master.monitor().reports_dropped());
  publish_drops(run, DropCounter::warnings_dropped, master.diagnostics().warnings_dropped());
  publish_drops(run, DropCounter::capture_frames_dropped, g_run.capture_queue.stats().frames_dropped);
  publish_drops(run, DropCounter::power_cycle_reports_dropped, handler.power_cycle_reports_dropped());
}

// Records of the segment each task refused as damaged, as this process last published them into its
// health slot (segment_records_report.hpp).
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): one writer per entry, the task of the slot
std::array<std::uint64_t, kRunHealthSlots> g_damaged_published{};
void publish_damaged(const TaskLoopPorts& ports, StatTask slot, std::uint64_t total) noexcept {
  publish_damaged_records(*ports.health, total, g_damaged_published[static_cast<std::size_t>(slot)]);
}

// The rescue RC task (task 0) published that its rescue motion is in `phase`.
bool rescue_motion_in(const Seqlock<RcTaskState>& rescue_state, kin::RescuePhase phase) noexcept {
  RcTaskState rescue{};
  return rescue_state.try_read(rescue) && rescue.phase == static_cast<std::uint8_t>(phase);
}

void handler_task(EthercatHandler& handler, ScenarioRunner& scenario, const FirmwareOptions& options, hal::Clock& clock,
                  const TaskLoopPorts& ports) noexcept {
  RunControl& state = *ports.run;
  TaskStats stats = start_task("ethercat", TaskId::ethercat_handler, StatTask::ethercat_handler, ports);
  TaskHealthProbe health(*ports.health);
  drivers::JointBus& bus = handler.bus();
  const hal::Nanoseconds started = clock.now();
  hal::Nanoseconds stop_at = options.duration > 0 ? started + options.duration : -1;
  hal::Nanoseconds stopping_since = -1;
  TaskTiming& timing = task_timing();
  std::atomic<std::int64_t>& heartbeat = *ports.heartbeat_ns;
  // Periods count from the handler's first period: the time since the bring-up (forking the tasks)
  // is start-up, not periods missed (period_schedule.hpp).
  bus.master().realign_schedule();
  const std::uint64_t skipped_at_start = bus.master().skipped_periods();
  std::uint64_t skipped_seen = skipped_at_start;
  for (;;) {
    const hal::Nanoseconds release = bus.next_wakeup();
    // The clock read at once after the wake-up, before any work (as cyclictest measures it).
    const hal::Nanoseconds woke = wake_at(clock, release);
    const std::uint64_t work_start = timing.timer.start();
    const drivers::JointCycleResult r = run_handler_cycle(handler);
    const std::uint64_t work_end = timing.timer.stop();
    const hal::Nanoseconds now = clock.now();
    stats.period(release, woke, work_start, work_end, hal::kNsPerMs / 2);
    heartbeat.store(now, std::memory_order_release);
    // Periods that had no cycle (the master skipped them to keep the phase after an overrun, a late
    // wake-up or a stall) are the handler's missed periods too: one figure in `ctl master`, `ctl
    // tasks` and the run's summary.
    const std::uint64_t skipped_total = bus.master().skipped_periods();
    if (skipped_total != skipped_seen) {
      stats.skipped(skipped_total - skipped_seen);
      skipped_seen = skipped_total;
    }
    // Late periods: cycles that started more than 0.5 ms after their period began, plus periods
    // that had no cycle at all (skipped to keep the phase after an overrun or a late wake-up).
    const std::uint64_t late_periods = stats.missed();
    // ctl master, ctl diag (and its reset), ctl slaves -v: through the handler's ports.
    run_handler_publish(handler, r, now, late_periods);
    publish_handler_drops(state, handler);
    publish_damaged(ports, StatTask::ethercat_handler, damaged_records_of(handler));
    state.cycles.store(r.cycle, std::memory_order_relaxed);
    state.late_periods.store(late_periods, std::memory_order_relaxed);
    const bool op = r.state == ecat::MasterState::op;
    if (op && !state.op.load(std::memory_order_relaxed)) {
      state.op_at.store(now, std::memory_order_relaxed);
      state.op.store(true, std::memory_order_release);
    }
    const bool forwarding = options.scenario.rescue_motion && rescue_motion_in(*ports.rescue_state, kin::RescuePhase::forwarding);
    if (scenario.on_cycle(now, op, forwarding)) {
      state.scenario_ok.store(scenario.action_status().ok(), std::memory_order_relaxed);
      state.scenario_at.store(scenario.acted_at(), std::memory_order_relaxed);
      state.scenario_acted.store(true, std::memory_order_release);
      if (options.duration == 0) stop_at = now + options.scenario.run_on;
    }
    // The rescue scenario ends once the rescue motion reached its end (run_on only bounds it): a
    // slow host stretches the motion in wall time, and that must not fail the run.
    if (options.duration == 0 && options.scenario.rescue_motion && stopping_since < 0 &&
        state.scenario_acted.load(std::memory_order_relaxed) && rescue_motion_in(*ports.rescue_state, kin::RescuePhase::done)) {
      const hal::Nanoseconds settled = now + kRescueSettle;
      if (settled < stop_at) stop_at = settled;
    }
    if (stopping_since < 0 && (stop_requested(state) || (stop_at >= 0 && now >= stop_at))) {
      handler.stop_drives();
      stopping_since = now;
    }
    if (stopping_since >= 0 && (handler.drives_disabled() || now - stopping_since >= kDisableTimeout)) break;
  }
  stats.publish();
  health.report();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    state.missed_cycles[j].store(handler.missed_cycles(joint_bit(j)), std::memory_order_relaxed);
  }
  state.frames_missing.store(handler.frames_missing(), std::memory_order_relaxed);
  const ecat::RingStatus& ring = bus.master().ring_status();
  state.ring_state.store(static_cast<std::uint8_t>(ring.state), std::memory_order_relaxed);
  state.ring_breaks.store(ring.breaks, std::memory_order_relaxed);
  state.ring_repairs.store(ring.repairs, std::memory_order_relaxed);
  state.ring_repeats.store(bus.master().link().stats().ring_repeats, std::memory_order_relaxed);
  state.skipped_periods.store(bus.master().skipped_periods() - skipped_at_start, std::memory_order_relaxed);
  state.drives_disabled.store(handler.drives_disabled(), std::memory_order_relaxed);
  const MotionIntakeCounters intake = handler.motion_intake().counters();
  state.intake_owned_periods.store(intake.owned_periods, std::memory_order_relaxed);
  state.intake_used_periods.store(intake.used_periods, std::memory_order_relaxed);
  state.intake_misses.store(intake.misses, std::memory_order_relaxed);
  state.intake_releases.store(intake.releases, std::memory_order_relaxed);
  const SentMotionFigures& sent = handler.motion_intake().sent_figures();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    state.sent_max_speed_rad_s[j].store(sent.max_speed_rad_s[j], std::memory_order_relaxed);
    state.sent_max_acceleration_rad_s2[j].store(sent.max_acceleration_rad_s2[j], std::memory_order_relaxed);
    state.sent_max_jerk_rad_s3[j].store(sent.max_jerk_rad_s3[j], std::memory_order_relaxed);
  }
  state.handler_done.store(true, std::memory_order_release);
}

void joint_manager_task(JointManager& manager, hal::Clock& clock, const TaskLoopPorts& ports) noexcept {
  RunControl& state = *ports.run;
  TaskStats stats = start_task("joint-manager", TaskId::joint_manager, StatTask::joint_manager, ports);
  TaskHealthProbe health(*ports.health);
  // Each step publishes the joints' status through the joint manager's port (JointManagerPorts::joint_status).
  run_periods(state.manager_stop, clock, kJointManagerPeriod, kJointManagerPeriod / 2, ports, stats,
              [&manager, &state, &ports](hal::Nanoseconds start) noexcept {
                manager.step(start);
                publish_damaged(ports, StatTask::joint_manager, damaged_records_of(manager));
                publish_drops(state, DropCounter::joint_events_dropped, g_run.tasks.joint_events->dropped());
                publish_drops(state, DropCounter::outcomes_deferred, manager.outcomes_deferred());
              });
  // The last answers and marks. The periods are over: a write of the file still in flight (or failing)
  // is waited for here, within kFileDrainLimit, so the run's end says whether the file is current.
  const hal::Nanoseconds drain_until = clock.now() + kFileDrainLimit;
  for (;;) {
    manager.step(clock.now());
    if (!manager.file_dirty() || clock.now() >= drain_until) break;
    clock.sleep_until(clock.now() + kJointManagerPeriod);
  }
  g_run.storage_stop.store(true, std::memory_order_release);
  publish_damaged(ports, StatTask::joint_manager, damaged_records_of(manager));
  stats.publish();
  health.report();
  state.lost_joints.store(manager.lost_joints(), std::memory_order_relaxed);
  state.lost_since_start.store(manager.lost_since_start(), std::memory_order_relaxed);
  state.condition.store(static_cast<std::uint8_t>(manager.summary().condition), std::memory_order_relaxed);
  state.file_dirty.store(manager.file_dirty(), std::memory_order_relaxed);
  state.manager_done.store(true, std::memory_order_release);
}

// An RC task (tasks/rescue_task.hpp, tasks/teleop_task.hpp): one period every kRcTaskPeriod, on the
// handler's clock (the heartbeats and reference times the handler's motion intake compares with its own).
template <typename Task>
void rc_task(Task& task, const char* name, StatTask slot, hal::Clock& clock, const TaskLoopPorts& ports) noexcept {
  const RunControl& state = *ports.run;
  TaskStats stats = start_task(name, TaskId::rc_tasks, slot, ports);
  TaskHealthProbe health(*ports.health);
  run_periods(state.rc_stop, clock, kRcTaskPeriod, kRcTaskPeriod / 2, ports, stats,
              [&task, &ports, slot](hal::Nanoseconds start) noexcept {
                task.period(start);
                publish_damaged(ports, slot, damaged_records_of(task.counters()));
              });
  stats.publish();
  health.report();
}

// The message parser: requests -> joint handle queue (its only producer), RC-task inputs.
void parser_task(MessageParser& parser, hal::Clock& clock, const TaskLoopPorts& ports) noexcept {
  RunControl& state = *ports.run;
  TaskStats stats = start_task("message-parser", TaskId::message_parser, StatTask::message_parser, ports);
  TaskHealthProbe health(*ports.health);
  run_periods(state.operator_stop, clock, kParserPeriod, 10 * kParserPeriod, ports, stats,
              [&parser, &state, &ports](hal::Nanoseconds start) noexcept {
                parser.step(start);
                publish_damaged(ports, StatTask::message_parser, damaged_records_of(parser));
                publish_drops(state, DropCounter::replies_dropped, parser.replies_dropped());
              });
  stats.publish();
  health.report();
}

// The socket handler: waits on both ports (bounded), then a bounded batch per wake-up.
void socket_task(SocketHandler& socket, hal::Clock& clock, const TaskLoopPorts& ports) noexcept {
  RunControl& state = *ports.run;
  TaskStats stats = start_task("socket-handler", TaskId::socket_handler, StatTask::socket_handler, ports);
  TaskHealthProbe health(*ports.health);
  const hal::TscTimer& timer = task_timing().timer;
  while (!state.operator_stop.load(std::memory_order_acquire)) {
    socket.wait(kSocketWaitMs);
    const hal::Nanoseconds start = clock.now();
    const std::uint64_t work_start = timer.start();
    socket.step(start);
    stats.period(start, start, work_start, timer.stop(), hal::kNsPerSec);
    ports.heartbeat_ns->store(clock.now(), std::memory_order_release);
    publish_drops(state, DropCounter::requests_dropped, socket.counters().forwarded_dropped);
    publish_damaged(ports, StatTask::socket_handler, damaged_records_of(socket));
  }
  // A restarted socket handler keeps its predecessors' maximum.
  std::uint64_t seen = state.socket_max_per_wakeup.load(std::memory_order_relaxed);
  while (socket.max_per_wakeup() > seen &&
         !state.socket_max_per_wakeup.compare_exchange_weak(seen, socket.max_per_wakeup(), std::memory_order_relaxed)) {
  }
  stats.publish();
  health.report();
}

}  // namespace

// The port wiring: each loop is given its ports (TaskPorts::task_loop); its object has its own.
void run_handler() noexcept {
  handler_task(*g_run.tasks.handler, *g_run.tasks.scenario, *g_run.tasks.options, *g_run.tasks.clock,
               g_run.tasks.ports->task_loop(StatTask::ethercat_handler));
}
void run_manager() noexcept {
  joint_manager_task(*g_run.tasks.manager, *g_run.tasks.clock, g_run.tasks.ports->task_loop(StatTask::joint_manager));
}
void run_parser() noexcept {
  parser_task(*g_run.tasks.parser, *g_run.tasks.operator_clock, g_run.tasks.ports->task_loop(StatTask::message_parser));
}
void run_socket() noexcept {
  socket_task(*g_run.tasks.socket, *g_run.tasks.operator_clock, g_run.tasks.ports->task_loop(StatTask::socket_handler));
}
void run_rc_rescue() noexcept {
  rc_task(*g_run.tasks.rc_rescue, "rc-rescue", StatTask::rc_rescue, *g_run.tasks.clock, g_run.tasks.ports->task_loop(StatTask::rc_rescue));
}
void run_rc_teleop() noexcept {
  rc_task(*g_run.tasks.rc_teleop, "rc-teleop", StatTask::rc_teleop, *g_run.tasks.clock, g_run.tasks.ports->task_loop(StatTask::rc_teleop));
}

void run_storage_worker() noexcept {
  // Named for `ps -L` and /proc (not the process's name): a thread of the joint manager's process.
  const Status named = hal::name_this_thread("joints-storage");
  if (!named.ok()) (void)std::printf("joints-storage: thread not named: %s\n", named.error().what);
  ErrorJointsStorageWorker& worker = *g_run.tasks.storage_worker;
  hal::MonotonicClock clock;  // a normal-priority thread: it may wait, for the disk and here
  for (;;) {
    const bool stopping = g_run.storage_stop.load(std::memory_order_acquire);
    if (worker.serve_one()) continue;
    if (stopping && !worker.holding()) break;
    clock.sleep_until(clock.now() + kStorageWorkerPoll);
  }
}

}  // namespace rescue::app::runner
