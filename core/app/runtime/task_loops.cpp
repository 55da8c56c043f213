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
#include "core/app/runtime/stop_signal.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/memory/heap_guard.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "hal/rt/rt_setup.hpp"

namespace rescue::app::runner {
namespace {

// Priorities and CPUs: each task's row of the task table (runtime/task_table.cpp; numbers in
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
bool stop_requested() noexcept { return stop_signal() != 0 || run().stop.load(std::memory_order_acquire); }

// Heap allocations and page faults of a task after its init (run_control.hpp, TaskHealth): taken
// when the task is past its set-up, reported in its slot at its end.
class TaskHealthProbe {
 public:
  explicit TaskHealthProbe(StatTask id) noexcept
      : slot_(&run().health[static_cast<std::size_t>(id)]),
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
// for `ctl tasks`) and its page faults since its set-up, recorded when it ends.
class TaskStats {
 public:
  TaskStats(StatTask id, const char* name, int cpu, int priority) noexcept : recorder_(&task_timing()[id]) {
    recorder_->start(links().task_stats[static_cast<std::size_t>(id)], name, cpu, priority, task_timing().ns_per_tick());
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
TaskStats start_task(const char* name, TaskId id, StatTask slot) noexcept {
  apply_task_rt(name, id);
  TaskStats stats(slot, name, task_cpu(id), task_priority(id));
  run().tasks_started.fetch_add(1, std::memory_order_release);
  return stats;
}

// A periodic task's loop (period_schedule.hpp): missed periods skipped and counted, its heartbeat
// published in its slot of TaskLinks::task_heartbeat_ns every period.
template <typename Work>
void run_periods(const std::atomic<bool>& stop, hal::Clock& clock, hal::Nanoseconds period,
                 hal::Nanoseconds late_after, StatTask slot, TaskStats& stats, Work work) noexcept {
  app::run_periods(stop, clock, task_timing().timer, period, late_after, stats,
                   links().task_heartbeat_ns[static_cast<std::size_t>(slot)], work);
}

// A queue's drop counter in the segment (run_control.hpp), written by the task at its producing end:
// what this process's object counted since it last published (a restarted task process adds its own).
// NOLINTNEXTLINE(cppcoreguidelines-avoid-non-const-global-variables): one writer per entry, the producing task
std::array<std::uint64_t, kDropCounters> g_drops_published{};
void publish_drops(DropCounter which, std::uint64_t count) noexcept {
  const auto i = static_cast<std::size_t>(which);
  if (count == g_drops_published[i]) return;
  run().dropped[i].fetch_add(count - g_drops_published[i], std::memory_order_relaxed);
  g_drops_published[i] = count;
}

void publish_handler_drops(EthercatHandler& handler) noexcept {
  const ecat::Master& master = handler.bus().master();
  publish_drops(DropCounter::events_dropped, handler.events_dropped());
  publish_drops(DropCounter::reports_dropped, master.monitor().reports_dropped());
  publish_drops(DropCounter::warnings_dropped, master.diagnostics().warnings_dropped());
  publish_drops(DropCounter::capture_frames_dropped, g_run.capture_queue.stats().frames_dropped);
  publish_drops(DropCounter::power_cycle_reports_dropped, handler.power_cycle_reports_dropped());
}

std::uint16_t saturate16(std::uint32_t v) noexcept { return v > 0xFFFFu ? std::uint16_t{0xFFFF} : static_cast<std::uint16_t>(v); }

// The link-quality counters for `ctl diag`, published once per completed round-robin sweep (every
// 23 reads, i.e. diag_interval_cycles x 23 periods), never per period: the copy is ~1 KiB.
// A reset (ctl diag --reset) publishes the zeroed table at once.
void publish_link_diag(const ecat::LinkDiagnostics& d, std::uint64_t cycle, std::uint64_t& published_sweeps,
                       std::uint64_t& published_resets) noexcept {
  if (d.sweeps() == published_sweeps && d.resets() == published_resets) return;
  published_sweeps = d.sweeps();
  published_resets = d.resets();
  protocol::DiagPayload out{};
  out.cycle = cycle;
  out.sweeps = d.sweeps();
  out.count = static_cast<std::uint8_t>(drivers::kRobotNetworkPlan.size());
  static_assert(drivers::kRobotNetworkPlan.size() <= protocol::kMaxSlaves, "every slave fits one diag message");
  static_assert(ecat::kEscPorts == protocol::kDiagPorts, "one record per ESC port");
  for (std::size_t p = 0; p < drivers::kRobotNetworkPlan.size(); ++p) {
    const ecat::SlaveErrorCounters& c = d.counters(p);
    protocol::DiagSlaveRecord& s = out.slaves[p];
    for (unsigned n = 0; n < ecat::kEscPorts; ++n) {
      s.ports[n].invalid_frames = saturate16(c.ports[n].invalid_frames);
      s.ports[n].rx_errors = saturate16(c.ports[n].rx_errors);
      s.ports[n].forwarded_errors = saturate16(c.ports[n].forwarded_errors);
      s.ports[n].lost_links = saturate16(c.ports[n].lost_links);
      if (d.warned(p, n)) s.warned = static_cast<std::uint8_t>(s.warned | (1U << n));
      if (d.ever_warned(p, n)) s.warned_before = static_cast<std::uint8_t>(s.warned_before | (1U << n));
    }
    s.processing_unit_errors = saturate16(c.processing_unit_errors);
    s.pdi_errors = saturate16(c.pdi_errors);
    s.reads = saturate16(c.reads);
  }
  links().link_diag.write(out);
}

// ctl diag --reset: a request the socket handler posted (TaskLinks::diag_reset) is taken here, once
// per period, by one atomic load: the master zeroes those slaves' counters (and clears their ESCs'
// in the next frames), the zeroed table is published, then the request is marked done.
void take_diag_reset(ecat::Master& master, std::uint64_t cycle, std::uint64_t& published_sweeps,
                     std::uint64_t& published_resets) noexcept {
  DiagResetLink& link = links().diag_reset;
  const std::uint64_t word = link.requested.load(std::memory_order_acquire);
  const std::uint64_t generation = DiagResetLink::generation_of(word);
  if (generation == 0 || generation == link.done.load(std::memory_order_relaxed)) return;
  master.reset_diagnostics(DiagResetLink::slaves_of(word));
  publish_link_diag(master.diagnostics(), cycle, published_sweeps, published_resets);
  link.done.store(generation, std::memory_order_release);
}

// ctl slaves -v: each slave's SII identity (bring-up) and the AL status and code the master read
// last, published when one of them changed (never per period: the copy is ~700 bytes).
void publish_slave_info(const ecat::Master& master, std::uint64_t cycle, protocol::SlaveInfoTable& published) noexcept {
  constexpr std::size_t kCount = drivers::kRobotNetworkPlan.size();
  static_assert(kCount <= protocol::kMaxSlaves, "every slave fits one slave_info message");
  bool changed = published.cycle == 0;
  for (std::size_t p = 0; p < kCount && !changed; ++p) {
    const protocol::SlaveInfoRecord& r = published.slaves[p];
    changed = r.al_status != master.last_al_status(p) || r.al_status_code != master.last_al_status_code(p) ||
              ((r.flags & protocol::kSlaveInfoAlRead) != 0) != master.al_status_read(p);
  }
  if (!changed) return;
  published.cycle = cycle == 0 ? 1 : cycle;
  published.count = static_cast<std::uint8_t>(kCount);
  for (std::size_t p = 0; p < kCount; ++p) {
    protocol::SlaveInfoRecord& r = published.slaves[p];
    r = protocol::SlaveInfoRecord{};
    r.position = static_cast<std::uint16_t>(p);
    r.station = drivers::kRobotNetworkPlan[p].station_address;
    if (const ecat::FoundSlave* id = master.identity(p); id != nullptr) {
      r.vendor_id = id->vendor_id;
      r.product_code = id->product_code;
      r.revision = id->revision;
      r.serial_number = id->serial_number;
      r.flags |= protocol::kSlaveInfoIdentity;
    }
    r.al_status = master.last_al_status(p);
    r.al_status_code = master.last_al_status_code(p);
    if (master.al_status_read(p)) r.flags |= protocol::kSlaveInfoAlRead;
  }
  links().slave_info.write(published);
}

// The rescue RC task (task 0) published that its rescue motion reached its end.
bool rescue_motion_done() noexcept {
  RcTaskState rescue{};
  return links().motion.task_state[0].try_read(rescue) && rescue.phase == static_cast<std::uint8_t>(kin::RescuePhase::done);
}

void handler_task(EthercatHandler& handler, ScenarioRunner& scenario, const FirmwareOptions& options, hal::Clock& clock) noexcept {
  RunControl& state = run();
  TaskStats stats = start_task("ethercat", TaskId::ethercat_handler, StatTask::ethercat_handler);
  TaskHealthProbe health(StatTask::ethercat_handler);
  drivers::JointBus& bus = handler.bus();
  const hal::Nanoseconds started = clock.now();
  hal::Nanoseconds stop_at = options.duration > 0 ? started + options.duration : -1;
  hal::Nanoseconds stopping_since = -1;
  TaskTiming& timing = task_timing();
  MasterStatus master{};
  std::uint64_t diag_sweeps = 0;
  std::uint64_t diag_resets = 0;
  protocol::SlaveInfoTable slave_info{};
  std::atomic<std::int64_t>& heartbeat = links().task_heartbeat_ns[static_cast<std::size_t>(StatTask::ethercat_handler)];
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
    const drivers::JointCycleResult r = handler.cycle();
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
    master.state = static_cast<std::uint8_t>(r.state);
    master.cycles = r.cycle;
    master.frames_sent = r.cycle;
    master.frames_lost = handler.frames_missing();
    // Late periods: cycles that started more than 0.5 ms after their period began, plus periods
    // that had no cycle at all (skipped to keep the phase after an overrun or a late wake-up).
    master.late_periods = stats.missed();
    const std::int64_t dc_error = bus.last_cycle().dc_phase_error;  // the master's own figure
    master.dc_deviation_ns = dc_error;
    const std::int64_t abs_dc = dc_error < 0 ? -dc_error : dc_error;
    if (abs_dc > master.dc_max_deviation_ns) master.dc_max_deviation_ns = abs_dc;
    master.in_exchange = bus.master().monitor().in_exchange();
    master.lost = bus.master().monitor().lost();
    static_assert(protocol::kMaxSlaves <= ecat::kMaxSlaves, "every published slave is one of the master's");
    for (std::size_t p = 0; p < protocol::kMaxSlaves; ++p) {
      const ecat::Master& m = bus.master();
      master.recovery[p] = static_cast<std::uint8_t>(m.recovery_state(p));
      const hal::Nanoseconds changed = m.recovery_changed_at(p);
      const hal::Nanoseconds age_ms = changed > 0 && now >= changed ? (now - changed) / hal::kNsPerMs : -1;
      master.recovery_age_ms[p] = age_ms < 0 || age_ms >= protocol::kRecoveryAgeNever ? protocol::kRecoveryAgeNever : static_cast<std::uint32_t>(age_ms);
    }
    links().master_status.write(master);
    publish_link_diag(bus.master().diagnostics(), r.cycle, diag_sweeps, diag_resets);
    take_diag_reset(bus.master(), r.cycle, diag_sweeps, diag_resets);
    publish_slave_info(bus.master(), r.cycle, slave_info);
    publish_handler_drops(handler);
    state.cycles.store(r.cycle, std::memory_order_relaxed);
    state.late_periods.store(master.late_periods, std::memory_order_relaxed);
    const bool op = r.state == ecat::MasterState::op;
    if (op && !state.op.load(std::memory_order_relaxed)) {
      state.op_at.store(now, std::memory_order_relaxed);
      state.op.store(true, std::memory_order_release);
    }
    if (scenario.on_cycle(now, op)) {
      state.scenario_ok.store(scenario.action_status().ok(), std::memory_order_relaxed);
      state.scenario_at.store(scenario.acted_at(), std::memory_order_relaxed);
      state.scenario_acted.store(true, std::memory_order_release);
      if (options.duration == 0) stop_at = now + options.scenario.run_on;
    }
    // The rescue scenario ends once the rescue motion reached its end (run_on only bounds it): a
    // slow host stretches the motion in wall time, and that must not fail the run.
    if (options.duration == 0 && options.scenario.rescue_motion && stopping_since < 0 &&
        state.scenario_acted.load(std::memory_order_relaxed) && rescue_motion_done()) {
      const hal::Nanoseconds settled = now + kRescueSettle;
      if (settled < stop_at) stop_at = settled;
    }
    if (stopping_since < 0 && (stop_requested() || (stop_at >= 0 && now >= stop_at))) {
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
  state.skipped_periods.store(bus.master().skipped_periods() - skipped_at_start, std::memory_order_relaxed);
  state.drives_disabled.store(handler.drives_disabled(), std::memory_order_relaxed);
  const MotionIntakeCounters intake = handler.motion_intake().counters();
  state.intake_owned_periods.store(intake.owned_periods, std::memory_order_relaxed);
  state.intake_used_periods.store(intake.used_periods, std::memory_order_relaxed);
  state.intake_misses.store(intake.misses, std::memory_order_relaxed);
  state.intake_releases.store(intake.releases, std::memory_order_relaxed);
  state.handler_done.store(true, std::memory_order_release);
}

void joint_manager_task(JointManager& manager, hal::Clock& clock) noexcept {
  RunControl& state = run();
  TaskStats stats = start_task("joint-manager", TaskId::joint_manager, StatTask::joint_manager);
  TaskHealthProbe health(StatTask::joint_manager);
  run_periods(state.manager_stop, clock, kJointManagerPeriod, kJointManagerPeriod / 2, StatTask::joint_manager, stats,
              [&manager](hal::Nanoseconds start) noexcept {
                manager.step(start);
                links().joint_status.write(published_status(manager.statuses()));
                publish_drops(DropCounter::joint_events_dropped, g_run.tasks.joint_events->dropped());
                publish_drops(DropCounter::outcomes_deferred, manager.outcomes_deferred());
              });
  // The last answers and marks. The periods are over: a write of the file still in flight (or failing)
  // is waited for here, within kFileDrainLimit, so the run's end says whether the file is current.
  const hal::Nanoseconds drain_until = clock.now() + kFileDrainLimit;
  for (;;) {
    manager.step(clock.now());
    links().joint_status.write(published_status(manager.statuses()));
    if (!manager.file_dirty() || clock.now() >= drain_until) break;
    clock.sleep_until(clock.now() + kJointManagerPeriod);
  }
  g_run.storage_stop.store(true, std::memory_order_release);
  stats.publish();
  health.report();
  state.lost_joints.store(manager.lost_joints(), std::memory_order_relaxed);
  state.lost_since_start.store(manager.lost_since_start(), std::memory_order_relaxed);
  state.condition.store(static_cast<std::uint8_t>(manager.summary().condition), std::memory_order_relaxed);
  state.file_dirty.store(manager.file_dirty(), std::memory_order_relaxed);
  state.manager_done.store(true, std::memory_order_release);
}

// An RC task (tasks/rc_task.hpp): one period every kRcTaskPeriod, on the handler's clock (the
// heartbeats and reference times the handler's motion intake compares with its own).
void rc_task(RcTask& task, hal::Clock& clock) noexcept {
  const RunControl& state = run();
  const bool rescue = task.id() == RcTaskId::rescue;
  const char* name = rescue ? "rc-rescue" : "rc-teleop";
  const StatTask slot = rescue ? StatTask::rc_rescue : StatTask::rc_teleop;
  TaskStats stats = start_task(name, TaskId::rc_tasks, slot);
  TaskHealthProbe health(slot);
  run_periods(state.rc_stop, clock, kRcTaskPeriod, kRcTaskPeriod / 2, slot, stats,
              [&task](hal::Nanoseconds start) noexcept { task.period(start); });
  stats.publish();
  health.report();
}

// The message parser: requests -> joint handle queue (its only producer), RC-task inputs.
void parser_task(MessageParser& parser, hal::Clock& clock) noexcept {
  const RunControl& state = run();
  TaskStats stats = start_task("message-parser", TaskId::message_parser, StatTask::message_parser);
  TaskHealthProbe health(StatTask::message_parser);
  run_periods(state.operator_stop, clock, kParserPeriod, 10 * kParserPeriod, StatTask::message_parser, stats,
              [&parser](hal::Nanoseconds start) noexcept {
                parser.step(start);
                publish_drops(DropCounter::replies_dropped, parser.replies_dropped());
              });
  stats.publish();
  health.report();
}

// The socket handler: waits on both ports (bounded), then a bounded batch per wake-up.
void socket_task(SocketHandler& socket, hal::Clock& clock) noexcept {
  RunControl& state = run();
  TaskStats stats = start_task("socket-handler", TaskId::socket_handler, StatTask::socket_handler);
  TaskHealthProbe health(StatTask::socket_handler);
  const hal::TscTimer& timer = task_timing().timer;
  while (!state.operator_stop.load(std::memory_order_acquire)) {
    socket.wait(kSocketWaitMs);
    const hal::Nanoseconds start = clock.now();
    const std::uint64_t work_start = timer.start();
    socket.step(start);
    stats.period(start, start, work_start, timer.stop(), hal::kNsPerSec);
    links().task_heartbeat_ns[static_cast<std::size_t>(StatTask::socket_handler)].store(clock.now(), std::memory_order_release);
    publish_drops(DropCounter::requests_dropped, socket.counters().forwarded_dropped);
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

void run_handler() noexcept {
  handler_task(*g_run.tasks.handler, *g_run.tasks.scenario, *g_run.tasks.options, *g_run.tasks.clock);
}
void run_manager() noexcept { joint_manager_task(*g_run.tasks.manager, *g_run.tasks.clock); }
void run_parser() noexcept { parser_task(*g_run.tasks.parser, *g_run.tasks.operator_clock); }
void run_socket() noexcept { socket_task(*g_run.tasks.socket, *g_run.tasks.operator_clock); }
void run_rc_rescue() noexcept { rc_task(*g_run.tasks.rc_rescue, *g_run.tasks.clock); }
void run_rc_teleop() noexcept { rc_task(*g_run.tasks.rc_teleop, *g_run.tasks.clock); }

void run_storage_worker() noexcept {
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
