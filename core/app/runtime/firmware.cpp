#include "core/app/runtime/firmware.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <thread>

#include "core/app/cli/cli.hpp"
#include "core/app/config/firmware_config.hpp"
#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_event_printer.hpp"
#include "core/app/tasks/joint_event_queue.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/rc_task.hpp"
#include "core/app/links/joint_sample_source.hpp"
#include "core/app/runtime/nic_factory.hpp"
#include "core/app/control/message_parser.hpp"
#include "core/app/control/predefined_messages.hpp"
#include "core/app/control/protocol_auth.hpp"
#include "core/app/control/replay_window.hpp"
#include "core/app/control/socket_handler.hpp"
#include "core/app/control/repaired_joints.hpp"
#include "core/app/sim/simulated_robot_instance.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "core/app/runtime/task_table.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/app/links/task_links.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "ecat/capture/capture_queue.hpp"
#include "ecat/capture/capture_tap.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/files/instance_lock.hpp"
#include "hal/files/state_dir.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {
namespace {

// Priorities, CPUs and periods: the task table (runtime/task_table.hpp, config/firmware_config.hpp).
// A configuration file (config/config_file.hpp) may have moved them before the run started.
int handler_priority() noexcept { return runner_priority(TaskId::ethercat_handler); }
int manager_priority() noexcept { return runner_priority(TaskId::joint_manager); }
int handler_cpu() noexcept { return task_spec(TaskId::ethercat_handler).cpu; }
int manager_cpu() noexcept { return task_spec(TaskId::joint_manager).cpu; }
int rc_task_priority() noexcept { return runner_priority(TaskId::rc_tasks); }
int rc_task_cpu() noexcept { return task_spec(TaskId::rc_tasks).cpu; }
constexpr hal::Nanoseconds kRcTaskPeriod = config::kRcTaskPeriodNs;
constexpr hal::Nanoseconds kJointManagerPeriod = config::kJointManagerPeriodNs;
constexpr hal::Nanoseconds kLoggerPeriod = config::kLoggerPeriodNs;
constexpr hal::Nanoseconds kDisableTimeout = config::kDisableTimeoutNs;
constexpr hal::Nanoseconds kParserPeriod = hal::kNsPerMs;
constexpr int kSocketWaitMs = 5;

// Everything the tasks use, in static storage: taken once at start-up, never from the heap.
TaskLinks g_links;

ecat::CaptureWriter g_capture;
// The handler's tap only copies frames into this queue; the logger thread writes them (the disk
// may block, the 1 ms cycle must not).
ecat::CaptureQueue g_capture_queue;
constexpr std::size_t kCaptureFramesPerLoggerPass = 256;

// The CPU a task asks for, or the machine's last one when it has fewer (announced by the RT report).
int cpu_for(int wanted) noexcept { return table_cpu_on_this_machine(wanted); }

void apply_thread_rt(const char* task, int priority, int cpu) noexcept {
  hal::RtConfig rt;
  rt.lock_memory = false;  // done once for the process
  rt.prefault_stack_bytes = hal::kTaskStackPrefaultBytes;  // what toolchain/rt_verify.py checks stacks against
  rt.fifo_priority = priority;
  rt.cpu = cpu_for(cpu);
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

double seconds(hal::Nanoseconds ns) noexcept { return static_cast<double>(ns) / static_cast<double>(hal::kNsPerSec); }

// Shared between the threads of the run.
struct RunState {
  std::atomic<bool> op{false};
  std::atomic<bool> handler_done{false};
  std::atomic<bool> manager_stop{false};
  std::atomic<bool> scenario_acted{false};
  std::atomic<std::int64_t> op_at{0};
  std::atomic<std::uint64_t> cycles{0};
  std::atomic<std::uint64_t> late_periods{0};  // as `ctl master` shows them
  std::atomic<int> tasks_started{0};  // tasks past their real-time set-up
  std::atomic<bool> operator_stop{false};  // socket handler and message parser
  std::atomic<bool> rc_stop{false};        // RC tasks
};

// Each task's page faults during its periods (hal::page_faults_of_thread), written by its thread
// when it ends, read by the main thread after joining it.
std::array<hal::PageFaults, kTaskStatSlots> g_task_page_faults{};

// A task's timing (runtime/task_timing.hpp's TaskRecorder: histograms, late periods, live figures
// for `ctl tasks`) and its page faults since its set-up, recorded when it ends.
class TaskStats {
 public:
  TaskStats(StatTask id, const char* name, int cpu, int priority) noexcept
      : recorder_(&task_timing()[id]),
        faults_(&g_task_page_faults[static_cast<std::size_t>(id)]),
        faults_at_start_(hal::page_faults_of_thread()) {
    recorder_->start(g_links.task_stats[static_cast<std::size_t>(id)], name, cpu, priority, task_timing().ns_per_tick());
  }
  // One period: due at `due_ns`, begun at `woke_ns`, its work between two TSC readings.
  void period(hal::Nanoseconds due_ns, hal::Nanoseconds woke_ns, std::uint64_t tsc_before, std::uint64_t tsc_after,
              hal::Nanoseconds late_after) noexcept {
    recorder_->period(due_ns, woke_ns, tsc_before, tsc_after, late_after);
  }
  // The last publication, when the task ends (its page faults since its set-up recorded too).
  void publish() noexcept {
    recorder_->publish();
    const hal::PageFaults now = hal::page_faults_of_thread();
    faults_->minor = now.minor - faults_at_start_.minor;
    faults_->major = now.major - faults_at_start_.major;
  }
  std::uint64_t missed() const noexcept { return recorder_->missed(); }

 private:
  TaskRecorder* recorder_;
  hal::PageFaults* faults_;
  hal::PageFaults faults_at_start_;
};

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
      (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": link %s: %s (first seen in cycle %" PRIu64 ")\n", t,
                        e.cycle, ecat::to_string(e.link.kind), names, e.link.detected_cycle);
      break;
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
    case HandlerEventKind::drives_disabled:
      (void)std::printf("[%8.3f s] ethercat: cycle %" PRIu64 ": every reachable drive disabled\n", t, e.cycle);
      break;
  }
}

std::uint16_t saturate16(std::uint32_t v) noexcept { return v > 0xFFFFu ? std::uint16_t{0xFFFF} : static_cast<std::uint16_t>(v); }

// The link-quality counters for `ctl diag`, published once per completed round-robin sweep (every
// 23 reads, i.e. diag_interval_cycles x 23 periods), never per period: the copy is ~1 KiB.
void publish_link_diag(const ecat::LinkDiagnostics& d, std::uint64_t cycle, std::uint64_t& published_sweeps) noexcept {
  if (d.sweeps() == published_sweeps) return;
  published_sweeps = d.sweeps();
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
  g_links.link_diag.write(out);
}

void handler_task(EthercatHandler& handler, ScenarioRunner& scenario, const FirmwareOptions& options, hal::Clock& clock,
                  RunState& state) noexcept {
  apply_thread_rt("ethercat", handler_priority(), handler_cpu());
  TaskStats stats(StatTask::ethercat_handler, "ethercat", cpu_for(handler_cpu()), handler_priority());
  state.tasks_started.fetch_add(1, std::memory_order_release);
  drivers::JointBus& bus = handler.bus();
  const hal::Nanoseconds started = clock.now();
  hal::Nanoseconds stop_at = options.duration > 0 ? started + options.duration : -1;
  hal::Nanoseconds stopping_since = -1;
  TaskTiming& timing = task_timing();
  MasterStatus master{};
  std::uint64_t diag_sweeps = 0;
  for (;;) {
    const hal::Nanoseconds release = bus.next_wakeup();
    clock.sleep_until(release);
    const std::uint64_t work_start = timing.timer.start();
    const drivers::JointCycleResult r = handler.cycle();
    const std::uint64_t work_end = timing.timer.stop();
    const hal::Nanoseconds now = clock.now();
    // Woke at now - the work's duration: no extra clock read.
    const hal::Nanoseconds woke = now - timing.timer.to_ns(work_end - work_start);
    stats.period(release, woke, work_start, work_end, hal::kNsPerMs / 2);
    master.state = static_cast<std::uint8_t>(r.state);
    master.cycles = r.cycle;
    master.frames_sent = r.cycle;
    master.frames_lost = handler.frames_missing();
    // Late periods: cycles that started more than 0.5 ms after their period began, plus periods
    // that had no cycle at all (skipped to keep the phase after an overrun or a late wake-up).
    master.late_periods = stats.missed() + bus.master().skipped_periods();
    const std::int64_t dc_error = bus.last_cycle().dc_phase_error;  // the master's own figure
    master.dc_deviation_ns = dc_error;
    const std::int64_t abs_dc = dc_error < 0 ? -dc_error : dc_error;
    if (abs_dc > master.dc_max_deviation_ns) master.dc_max_deviation_ns = abs_dc;
    master.in_exchange = bus.master().monitor().in_exchange();
    master.lost = bus.master().monitor().lost();
    g_links.master_status.write(master);
    publish_link_diag(bus.master().diagnostics(), r.cycle, diag_sweeps);
    state.cycles.store(r.cycle, std::memory_order_relaxed);
    state.late_periods.store(master.late_periods, std::memory_order_relaxed);
    const bool op = r.state == ecat::MasterState::op;
    if (op && !state.op.load(std::memory_order_relaxed)) {
      state.op_at.store(now, std::memory_order_relaxed);
      state.op.store(true, std::memory_order_release);
    }
    if (scenario.on_cycle(now, op)) {
      state.scenario_acted.store(true, std::memory_order_release);
      if (options.duration == 0) stop_at = now + options.scenario.run_on;
    }
    if (stopping_since < 0 && (stop_signal() != 0 || (stop_at >= 0 && now >= stop_at))) {
      handler.stop_drives();
      stopping_since = now;
    }
    if (stopping_since >= 0 && (handler.drives_disabled() || now - stopping_since >= kDisableTimeout)) break;
  }
  stats.publish();
  state.handler_done.store(true, std::memory_order_release);
}

void joint_manager_task(JointManager& manager, hal::Clock& clock, RunState& state) noexcept {
  apply_thread_rt("joint-manager", manager_priority(), manager_cpu());
  TaskStats stats(StatTask::joint_manager, "joint-manager", cpu_for(manager_cpu()), manager_priority());
  state.tasks_started.fetch_add(1, std::memory_order_release);
  hal::Nanoseconds next = clock.now();
  TaskTiming& timing = task_timing();
  while (!state.manager_stop.load(std::memory_order_acquire)) {
    const hal::Nanoseconds start = clock.now();
    const std::uint64_t work_start = timing.timer.start();
    manager.step(start);
    g_links.joint_status.write(published_status(manager.statuses()));
    stats.period(next, start, work_start, timing.timer.stop(), kJointManagerPeriod / 2);
    next += kJointManagerPeriod;
    clock.sleep_until(next);
  }
  manager.step(clock.now());  // the last answers and marks
  g_links.joint_status.write(published_status(manager.statuses()));
  stats.publish();
}

// An RC task (tasks/rc_task.hpp): one period every kRcTaskPeriod, on the handler's clock (the
// heartbeats and reference times the handler's motion intake compares with its own).
void rc_task_thread(RcTask& task, hal::Clock& clock, RunState& state) noexcept {
  const bool rescue = task.id() == RcTaskId::rescue;
  const char* name = rescue ? "rc-rescue" : "rc-teleop";
  apply_thread_rt(name, rc_task_priority(), rc_task_cpu());
  TaskStats stats(rescue ? StatTask::rc_rescue : StatTask::rc_teleop, name, cpu_for(rc_task_cpu()), rc_task_priority());
  state.tasks_started.fetch_add(1, std::memory_order_release);
  const hal::TscTimer& timer = task_timing().timer;
  hal::Nanoseconds next = clock.now();
  while (!state.rc_stop.load(std::memory_order_acquire)) {
    const hal::Nanoseconds start = clock.now();
    const std::uint64_t work_start = timer.start();
    task.period(start);
    stats.period(next, start, work_start, timer.stop(), kRcTaskPeriod / 2);
    next += kRcTaskPeriod;
    clock.sleep_until(next);
  }
  stats.publish();
}

// The message parser: requests -> joint handle queue (its only producer), RC-task inputs.
void parser_task(MessageParser& parser, hal::Clock& clock, RunState& state) noexcept {
  const TaskSpec& task = task_spec(TaskId::message_parser);
  apply_thread_rt("message-parser", runner_priority(task.id), task.cpu);
  TaskStats stats(StatTask::message_parser, "message-parser", cpu_for(task.cpu), runner_priority(task.id));
  state.tasks_started.fetch_add(1, std::memory_order_release);
  const hal::TscTimer& timer = task_timing().timer;
  hal::Nanoseconds next = clock.now();
  while (!state.operator_stop.load(std::memory_order_acquire)) {
    const hal::Nanoseconds start = clock.now();
    const std::uint64_t work_start = timer.start();
    parser.step(start);
    stats.period(next, start, work_start, timer.stop(), 10 * kParserPeriod);
    next += kParserPeriod;
    clock.sleep_until(next);
  }
  stats.publish();
}

// The socket handler: waits on both ports (bounded), then a bounded batch per wake-up.
void socket_task(SocketHandler& socket, hal::Clock& clock, RunState& state) noexcept {
  const TaskSpec& task = task_spec(TaskId::socket_handler);
  apply_thread_rt("socket-handler", runner_priority(task.id), task.cpu);
  TaskStats stats(StatTask::socket_handler, "socket-handler", cpu_for(task.cpu), runner_priority(task.id));
  state.tasks_started.fetch_add(1, std::memory_order_release);
  const hal::TscTimer& timer = task_timing().timer;
  while (!state.operator_stop.load(std::memory_order_acquire)) {
    socket.wait(kSocketWaitMs);
    const hal::Nanoseconds start = clock.now();
    const std::uint64_t work_start = timer.start();
    socket.step(start);
    stats.period(start, start, work_start, timer.stop(), hal::kNsPerSec);
  }
  stats.publish();
}

// The logger's side of the joint manager's events: prints what is queued, and how many a full queue
// dropped since the last pass.
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

// What the logger last printed of the motion (owner, RC task modes and phases).
struct MotionLog {
  std::uint64_t owner_word{MotionOwner::kNobody};
  std::array<RcTaskState, kRcTasksRun> last{};
  std::array<bool, kRcTasksRun> seen{};
  std::uint8_t rescue_phase_reached{0};
};

const char* rc_task_name(std::size_t task) noexcept { return task == 0 ? "rc-rescue" : "rc-teleop"; }

void print_motion_changes(MotionLog& log, hal::Nanoseconds at) noexcept {
  const std::uint64_t word = g_links.motion.owner.word();
  if (word != log.owner_word) {
    log.owner_word = word;
    const std::uint8_t task = MotionOwner::task_of(word);
    if (task == kNoOwnerTask) {
      (void)std::printf("[%8.3f s] motion: no owner (generation %" PRIu64 "): every enabled joint holds its reference\n",
                        seconds(at), MotionOwner::generation_of(word));
    } else {
      (void)std::printf("[%8.3f s] motion: owned by %s (RC task %u, generation %" PRIu64 ")\n", seconds(at),
                        task < kRcTasksRun ? rc_task_name(task) : "?", static_cast<unsigned>(task),
                        MotionOwner::generation_of(word));
    }
  }
  for (std::size_t k = 0; k < kRcTasksRun; ++k) {
    RcTaskState now{};
    if (!g_links.motion.task_state[k].try_read(now) || now.periods == 0) continue;
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
  while (g_links.local_replies.try_pop(reply)) {
    (void)std::printf("[%8.3f s] operator: %s: %s%s%s\n", seconds(at), protocol::to_string(reply.request_type),
                      reply.outcome == protocol::Outcome::accepted ? "accepted" : "refused: ",
                      reply.outcome == protocol::Outcome::accepted && reply.text[0] != '\0' ? "; " : "", reply.text.data());
  }
}

bool send_local(protocol::MessageType type, JointMask joints) noexcept {
  ControlRequest request;
  request.type = type;
  request.joints = joints;
  if (g_links.local_requests.try_push(request)) return true;
  (void)std::printf("operator: request queue full, %s dropped\n", protocol::to_string(type));
  return false;
}

// Whether the handler's latest published values show every joint of `joints` reachable.
bool all_reachable(JointMask joints) noexcept {
  RobotSample sample{};
  if (!g_links.samples.try_read(sample)) return false;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) != 0 && !sample[j].reachable) return false;
  }
  return true;
}

// A resource another instance holds: name it and the holder's pid; the run does not start.
int fail_locked(const char* what, const char* name, const Error& error) noexcept {
  if (error.code == Errc::busy) {
    if (error.detail0 != 0) {
      (void)std::fprintf(stderr, "rescue-motion run: %s %s is in use by another rescue-motion (pid %u); not starting\n",
                         what, name, error.detail0);
    } else {
      (void)std::fprintf(stderr, "rescue-motion run: %s %s is in use by another rescue-motion (pid unknown); not starting\n",
                         what, name);
    }
    return 1;
  }
  (void)std::fprintf(stderr, "rescue-motion run: cannot lock %s %s: %s (%s, errno %u); not starting\n", what, name,
                     error.what, to_string(error.code), error.detail0);
  return 1;
}

// One instance per state directory and per raw NIC; 0 when taken, else the exit status. A read-only
// state directory is warned about (a loss could not be recorded) and takes no lock.
int take_instance_locks(const FirmwareOptions& options, const char* dir) noexcept {
  // One instance per state directory and per raw NIC (a second one would erase the first's losses).
  const Status writable = hal::check_writable(dir);
  if (!writable.ok()) {
    (void)std::fprintf(stderr,
                       "rescue-motion run: WARNING: state directory %s is not writable (errno %u): a joint lost in this run "
                       "cannot be recorded, and no other instance is kept out; fix its permissions or use "
                       "--state-dir\n",
                       dir, writable.error().detail0);
  } else {
    const Status locked = hal::lock_state_directory(dir);
    if (!locked.ok()) return fail_locked("state directory", dir, locked.error());
  }
  if (options.nic.kind == NicKind::raw) {
    const Status locked = hal::lock_raw_interface(options.nic.interface_name.data());
    if (!locked.ok()) return fail_locked("interface", options.nic.interface_name.data(), locked.error());
  }
  return 0;
}

int report_bring_up_failure(drivers::JointBus& bus) noexcept {
  const ecat::BringUpReport& report = bus.master().report();
  (void)std::fprintf(stderr, "rescue-motion run: bring-up failed at %s: %s (%s)\n",
                     report.failed_step != nullptr ? report.failed_step : "?", report.error.what,
                     to_string(report.error.code));
  return 1;
}

// After the tasks stopped: the frames still queued are written, the figures printed, the file closed.
Status finish_capture(const char* path) noexcept {
  while (g_capture_queue.drain(g_capture, kCaptureFramesPerLoggerPass) != 0) {
  }
  const ecat::CaptureQueueStats queued = g_capture_queue.stats();
  (void)std::printf("rescue-motion run: capture %s: %" PRIu64 " frames, %" PRIu64 " write errors, %" PRIu64
                    " dropped (queue full)\n",
                    path, g_capture.stats().frames_written, g_capture.stats().write_errors, queued.frames_dropped);
  return g_capture.close();
}

void print_restored(JointMask restored) noexcept {
  if (restored == 0) return;
  char names[kJointNamesCapacity];
  format_joint_names(restored, names, sizeof names);
  (void)std::printf("rescue-motion run: restored lost joints %s from the error-joints file before bring-up; "
                    "they stay out of the exchange until an operator clears them\n",
                    names);
}

// What start-up did with a damaged error-joints file or an interrupted write: exactly what was salvaged,
// dropped and added, where the original is kept, and what the operator can do.
void print_restore_problems(const RestoreReport& r, const char* dir) noexcept {
  char kept[64];
  set_aside_name(r.set_aside_suffix, kept, sizeof kept);
  char names[kJointNamesCapacity];
  if (r.newer_temporary) {
    format_joint_names(r.from_temporary, names, sizeof names);
    (void)std::printf("rescue-motion run: %s/%s is complete and newer (sequence %" PRIu64 ") than the error-joints "
                      "file: a write was interrupted before its rename; its joints are kept recorded lost%s%s\n",
                      dir, ErrorJointsFileStorage::kTemporaryName, r.temporary_sequence,
                      r.from_temporary != 0 ? "; it adds " : "", r.from_temporary != 0 ? names : "");
  }
  if (!r.damaged()) return;
  const Error& why = r.file_status.error();
  if (r.salvaged == 0) {
    (void)std::printf("rescue-motion run: error-joints file not used: %s (%s); %u record(s) dropped; starting safely\n",
                      why.what, to_string(why.code), r.records_dropped);
    if (r.set_aside) (void)std::printf("rescue-motion run:   the original is kept as %s/%s\n", dir, kept);
    return;
  }
  format_joint_names(r.salvaged, names, sizeof names);
  (void)std::printf("rescue-motion run: error-joints file damaged: %s (%s); salvaged %s from the records that passed "
                    "their checks; dropped %u record(s) that did not\n",
                    why.what, to_string(why.code), names, r.records_dropped);
  if (r.added_behind != 0) {
    format_joint_names(r.added_behind, names, sizeof names);
    (void)std::printf("rescue-motion run:   also recorded lost: %s, behind a salvaged lost joint on its branch and "
                      "so unreachable too (held position unknown)\n",
                      names);
  }
  if (r.set_aside) (void)std::printf("rescue-motion run:   the damaged original is kept as %s/%s\n", dir, kept);
  format_joint_names(r.restored, names, sizeof names);
  (void)std::printf("rescue-motion run:   %s stay out of service (brought up if they answer, never driven); once "
                    "they are repaired and checked, clear them with --clear-joint %s\n",
                    names, names);
}

// A signal stopped the bring-up: nothing reached OP, no drive was enabled; exit 0.
int stopped_in_bring_up(drivers::JointBus& bus, const FirmwareOptions& options) noexcept {
  const ecat::BringUpReport& report = bus.master().report();
  (void)std::printf("rescue-motion run: stopped by signal %d during bring-up, before step %s; no drive was enabled "
                    "(no slave reached OP); error-joints file unchanged\n",
                    stop_signal(), report.failed_step != nullptr ? report.failed_step : "?");
  if (options.capture_path != nullptr) (void)finish_capture(options.capture_path);
  return 0;
}

// The one line saying where a signal stopped the run.
void print_stop_line(const RunState& state, bool drives_disabled, bool file_dirty) noexcept {
  (void)std::printf("rescue-motion run: stopped by signal %d %s, after %" PRIu64 " cycles; drives %s; error-joints "
                    "file %s\n",
                    stop_signal(), state.op.load() ? "while in OP" : "before OP (going to OP)", state.cycles.load(),
                    drives_disabled ? "disabled" : "told to disable (not all confirmed)",
                    file_dirty ? "NOT written" : "up to date");
}

// Prints what the operator's --clear-joint request will do; false when it is refused.
bool announce_repaired_joints(const RepairedJointsPlan& plan) noexcept {
  char names[kJointNamesCapacity];
  if (plan.not_recorded != 0) {
    format_joint_names(plan.not_recorded, names, sizeof names);
    (void)std::printf("rescue-motion run: --clear-joint: %s not recorded lost; nothing to clear\n", names);
  }
  if (plan.refused()) {
    format_joint_names(plan.stranded, names, sizeof names);
    char blocking[kJointNamesCapacity];
    format_joint_names(plan.blocking, blocking, sizeof blocking);
    (void)std::fprintf(stderr,
                       "rescue-motion run: --clear-joint: %s cannot answer behind %s, which stay(s) recorded lost: "
                       "clear those too; the error-joints file is unchanged\n",
                       names, blocking);
    return false;
  }
  if (plan.to_clear != 0) {
    format_joint_names(plan.to_clear, names, sizeof names);
    (void)std::printf("rescue-motion run: operator declares %s repaired: expected on the network, cleared once they "
                      "answer in OP\n",
                      names);
  }
  return true;
}

}  // namespace

int exit_status_for(fsm::RobotCondition condition) noexcept {
  return condition == fsm::RobotCondition::error ? kExitRobotError : 0;
}

namespace {
// The exit status of a run that stopped in order, said on stderr when it is not 0.
int robot_exit(fsm::RobotCondition condition) noexcept {
  const int status = exit_status_for(condition);
  if (status != 0) {
    (void)std::fprintf(stderr, "rescue-motion run: the robot ended in error (every joint in Error): exit status %d\n",
                       status);
  }
  return status;
}
}  // namespace

// A scenario's checks once the run stopped: 0, or the exit status after saying what failed.
int scenario_verdict(const Scenario& wanted, const ScenarioRunner& runner, JointMask lost, JointMask restored,
                     std::uint64_t healthy_missed, bool file_dirty, const MotionLog& motion,
                     const MotionIntakeCounters& intake) noexcept {
  if (wanted.kind == ScenarioKind::none) return 0;
  if (!runner.acted() || !runner.action_status().ok()) return fail("run", "the scenario's link cut did not happen");
  if ((lost & wanted.expected_lost) != wanted.expected_lost || (lost & ~(wanted.expected_lost | restored)) != 0) {
    return fail("run", "the joints marked lost differ from the joints behind the cut");
  }
  if (healthy_missed != 0) return fail("run", "healthy joints missed cycles during the link cut");
  if (file_dirty) return fail("run", "the error-joints file could not be written");
  if (wanted.rescue_motion) {
    if (intake.used_periods == 0) return fail("run", "the rescue RC task's references never drove the joints");
    if (motion.rescue_phase_reached != static_cast<std::uint8_t>(kin::RescuePhase::done)) {
      return fail("run", "the rescue motion did not reach its end before the stop");
    }
  }
  return 0;
}

// The run's figures as `key: value` lines (the last lines of every run), docs/motion-owner.md.
struct RunSummary {
  std::uint64_t cycles{0};
  std::uint64_t heap_allocations{0};
  JointMask lost{0};
  const SocketCounters* socket{nullptr};
  MotionIntakeCounters intake{};
  std::uint8_t rescue_phase_reached{0};
};

void print_run_summary(const RunSummary& s) noexcept {
  (void)std::printf("clock: wall (CLOCK_MONOTONIC); tasks: threads of one process\n");
  (void)std::printf("periods_run: %" PRIu64 "\n", s.cycles);
  for (std::size_t k = 0; k < kTaskStatSlots; ++k) {
    TaskStat stat{};
    if (!g_links.task_stats[k].try_read(stat) || stat.name[0] == '\0') continue;
    char key[protocol::kNameSize + 1];
    std::size_t n = 0;
    for (; n < protocol::kNameSize && stat.name[n] != '\0'; ++n) key[n] = stat.name[n] == '-' ? '_' : stat.name[n];
    key[n] = '\0';
    const hal::PageFaults& faults = g_task_page_faults[k];
    (void)std::printf("periods_run_%s: %" PRIu64 "\n", key, stat.periods);
    (void)std::printf("periods_missed_%s: %" PRIu64 "\n", key, stat.missed);
    (void)std::printf("max_execution_ns_%s: %" PRIu64 "\n", key, stat.max_execution_ns);
    (void)std::printf("page_faults_%s: %" PRIu64 "\n", key, faults.minor + faults.major);
  }
  (void)std::printf("heap_allocations_after_init: %" PRIu64 "\n", s.heap_allocations);
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
  if (g_links.motion.task_state[static_cast<std::size_t>(RcTaskId::rescue)].try_read(rescue)) {
    (void)std::printf("rescue_residual_left_m: %.4f\n", rescue.position_residual_m[0]);
    (void)std::printf("rescue_residual_right_m: %.4f\n", rescue.position_residual_m[1]);
  }
}

// The start-up sequence reads top to bottom as docs/firmware.md and docs/tasks.md describe it; its
// pieces are already helpers, and what remains is the wiring of the tasks' static objects.
// NOLINTNEXTLINE(readability-function-size)
int run_firmware(const FirmwareOptions& options) noexcept {
  static hal::SystemWallClock wall_clock;
  static JointEventQueue events;  // the joint manager's sink; the logger prints (never its thread)
  static JointEventPrinter event_printer(stdout, "joint-manager: ");
  static RunState state;

  // SIGINT/SIGTERM from the first instant: every phase (bring-up included) polls the flag and stops
  // cleanly, with one line saying where.
  if (!install_stop_handlers()) return fail("run", "cannot install SIGINT/SIGTERM handlers");

  // 1. The error-joints file, before the network (design brief section 6).
  const Result<hal::StateDir> dir = hal::resolve_state_dir(options.state_dir);
  if (!dir.ok()) return fail("run", "cannot use the state directory", dir.error());
  (void)std::printf("rescue-motion run: nic %s, scenario %s, state directory %s (%s)\n", options.nic_text,
                    options.scenario.name, dir.value().path.c_str(), dir.value().source);
  const int lock_status = take_instance_locks(options, dir.value().path.c_str());
  if (lock_status != 0) return lock_status;
  static ErrorJointsFileStorage storage(dir.value().path.c_str());
  static SpscMessageSource<LostJointsReport, TaskLinks::kReportQueueDepth> reports(g_links.lost_reports);
  static SpscMessageSink<JointManagerNotice, TaskLinks::kNoticeQueueDepth> notices(g_links.notices);
  static SpscMessageSource<JointCommand, TaskLinks::kCommandQueueDepth> commands(g_links.joint_commands);
  static SeqlockSampleSource samples(g_links.samples);
  static SeqlockDemandSink demand_sink(g_links.demand);
  static SpscMessageSink<JointCommandOutcome, TaskLinks::kOutcomeQueueDepth> outcomes(g_links.command_outcomes);
  static JointManager manager(JointManagerPorts{&reports, &notices, &commands, &samples, &storage, &wall_clock, &events,
                                                &demand_sink, &outcomes});
  manager.set_auto_clear_power_cycled(options.auto_clear_power_cycled);

  // The operator's path in: the message parser (the joint handle queue's only producer) and, with a
  // key, the socket handler. They see only queues and seqlocks of g_links.
  static SpscMessageSource<ControlRequest, TaskLinks::kRequestQueueDepth> parser_network(g_links.control_requests);
  static SpscMessageSource<ControlRequest, TaskLinks::kRequestQueueDepth> parser_local(g_links.local_requests);
  static SpscMessageSink<ControlReply, TaskLinks::kReplyQueueDepth> parser_replies(g_links.control_replies);
  static SpscMessageSink<ControlReply, TaskLinks::kReplyQueueDepth> parser_local_replies(g_links.local_replies);
  static SpscMessageSink<JointCommand, TaskLinks::kCommandQueueDepth> parser_out(g_links.joint_commands);
  static SpscMessageSource<JointCommandOutcome, TaskLinks::kOutcomeQueueDepth> parser_outcomes(g_links.command_outcomes);
  static SpscMessageSink<RcTaskInput, TaskLinks::kRcInputQueueDepth> rc0(g_links.rc_inputs[0]);
  static SpscMessageSink<RcTaskInput, TaskLinks::kRcInputQueueDepth> rc1(g_links.rc_inputs[1]);
  static SpscMessageSink<RcTaskInput, TaskLinks::kRcInputQueueDepth> rc2(g_links.rc_inputs[2]);
  static SpscMessageSink<RcTaskInput, TaskLinks::kRcInputQueueDepth> rc3(g_links.rc_inputs[3]);
  MessageParserPorts parser_ports;
  parser_ports.network = &parser_network;
  parser_ports.local = &parser_local;
  parser_ports.network_replies = &parser_replies;
  parser_ports.local_replies = &parser_local_replies;
  parser_ports.joint_commands = &parser_out;
  parser_ports.outcomes = &parser_outcomes;
  parser_ports.samples = &g_links.samples;
  parser_ports.joint_status = &g_links.joint_status;
  parser_ports.rc_inputs = {&rc0, &rc1, &rc2, &rc3};
  parser_ports.rc_heartbeat_ns = &g_links.rc_heartbeat_ns;
  static MessageParser parser(parser_ports);

  if (!protocol::init_crypto().ok()) return fail("run", "libsodium could not be initialised");
  hal::PathBuffer key_path;
  if (options.key_path != nullptr) {
    (void)std::snprintf(key_path.text.data(), key_path.text.size(), "%s", options.key_path);
  } else {
    const Result<hal::PathBuffer> joined = hal::join_path(dir.value().path.c_str(), "operator.key");
    if (!joined.ok()) return fail("run", "key file path", joined.error());
    key_path = joined.value();
  }
  const Result<protocol::Key> key = protocol::load_key_file(key_path.c_str());
  const bool operator_port = key.ok();
  if (!key.ok()) {
    if (options.key_path != nullptr || key.error().code != Errc::not_found) {
      (void)std::fprintf(stderr, "rescue-motion run: key file %s: %s\n", key_path.c_str(), key.error().what);
      return 1;
    }
    (void)std::printf("rescue-motion run: no key file %s: operator and sensor ports closed "
                      "(create one with: rescue-motion ctl keygen --key %s)\n",
                      key_path.c_str(), key_path.c_str());
  }
  static protocol::FileReplayStore replay_store(dir.value().path.c_str());
  static protocol::ReplayWindow replay(replay_store);
  static SpscMessageSink<ControlRequest, TaskLinks::kRequestQueueDepth> socket_requests(g_links.control_requests);
  static SpscMessageSource<ControlReply, TaskLinks::kReplyQueueDepth> socket_replies(g_links.control_replies);
  SocketHandlerPorts socket_ports;
  socket_ports.requests = &socket_requests;
  socket_ports.replies = &socket_replies;
  socket_ports.sensors = &g_links.sensors;
  socket_ports.counters = &g_links.socket_counters;
  socket_ports.samples = &g_links.samples;
  socket_ports.joint_status = &g_links.joint_status;
  socket_ports.master = &g_links.master_status;
  socket_ports.diag = &g_links.link_diag;
  socket_ports.tasks = &g_links.task_stats;
  socket_ports.motion = &g_links.motion;
  static SocketHandler socket(socket_ports, operator_port ? key.value() : protocol::Key{}, replay, wall_clock);
  if (operator_port) {
    const protocol::RestoreOutcome window = replay.restore(static_cast<std::uint64_t>(wall_clock.unix_time_ns()));
    if (!window.file_status.ok() && window.file_status.error().code != Errc::not_found) {
      (void)std::printf("rescue-motion run: replay-window file not used: %s; every sender starts at the robot's clock\n",
                        window.file_status.error().what);
    }
    SocketHandlerOptions socket_options;
    socket_options.listen = options.listen;
    socket_options.control_port = options.control_port;
    socket_options.sensor_port = options.sensor_port;
    const Status opened_ports = socket.open(socket_options);
    if (!opened_ports.ok()) return fail("run", "cannot open the UDP ports", opened_ports.error());
    (void)std::printf("rescue-motion run: operator control port %s:%u, sensor port %s:%u (key %s)\n", options.listen,
                      static_cast<unsigned>(socket.control_port()), options.listen,
                      static_cast<unsigned>(socket.sensor_port()), key_path.c_str());
  }

  static SelectedNic selected;
  const Status opened = selected.open(options.nic);
  if (!opened.ok()) return fail_nic("run", options.nic_text, opened.error());
  hal::Nic& nic = *selected.nic();
  hal::Clock& clock = nic.clock();
  const hal::Nanoseconds start = clock.now();
  event_printer.set_origin(start);

  const RestoreReport restored = manager.restore(clock.now());
  print_joint_events(events, event_printer);
  print_restored(restored.restored);
  // The operator's clear of repaired joints: they must answer at bring-up; the file changes only
  // once they do (a clear that cannot be confirmed loses nothing).
  const RepairedJointsPlan repaired = plan_repaired_joints(options.clear_joints, restored.restored);
  if (!announce_repaired_joints(repaired)) return 1;
  const JointMask to_clear = repaired.to_clear;
  const JointMask out_of_service = repaired.out_of_service;
  print_restore_problems(restored, dir.value().path.c_str());

  // 2. The machine: memory locked and prefaulted once (each task sets its own priority and CPU).
  hal::RtConfig process_rt;
  process_rt.lock_memory = true;
  const hal::RtReport rt = hal::apply_rt_config(process_rt);
  if (!rt.fully_applied()) rt.print(stdout);

  // 3. The network.
  static drivers::JointBus bus(nic);
  if (options.capture_path != nullptr) {
    ecat::CaptureWriterOptions capture_options;
    capture_options.timestamp_offset = ecat::unix_time_offset(clock);
    const Status capture = g_capture.open(options.capture_path, capture_options);
    if (!capture.ok()) return fail("run", "cannot open the capture file", capture.error());
    bus.master().set_tap(ecat::capture_tap, &g_capture);  // bring-up: this thread writes directly
  }
  ecat::MasterOptions master_options;
  master_options.stop_requested = []() noexcept { return stop_signal() != 0; };
  master_options.online_recovery = true;  // returning slaves back to OP while cycling (docs/master.md)

  (void)std::printf("rescue-motion run: bringing the EtherCAT network up\n");
  (void)std::fflush(stdout);
  const Status up = bus.bring_up(master_options, out_of_service);
  if (!up.ok() && stop_signal() != 0) return stopped_in_bring_up(bus, options);
  if (!up.ok()) {
    if (to_clear != 0) {
      (void)std::fprintf(stderr, "rescue-motion run: the error-joints file is unchanged: the joints declared repaired "
                                 "must answer at bring-up\n");
    }
    return report_bring_up_failure(bus);
  }
  const ecat::BringUpReport& bring_up = bus.master().report();
  (void)std::printf("rescue-motion run: %u slaves found, SAFE-OP after %.3f s, distributed clocks within %u ns\n",
                    static_cast<unsigned>(bring_up.slaves_counted), seconds(bring_up.safe_op_at - bring_up.started_at),
                    bring_up.dc_max_difference_ns);

  // 4. The tasks. From now on the handler's thread only queues captured frames.
  if (g_capture.is_open()) bus.master().set_tap(ecat::capture_queue_tap, &g_capture_queue);
  drivers::SimulatedSegment* segment =
      options.nic.kind == NicKind::sim ? &simulated_robot(clock.now()).segment() : nullptr;
  static EthercatHandler handler(bus, g_links, restored.restored);
  static ScenarioRunner scenario(options.scenario, segment);
  start_task_timing();
  (void)std::fflush(stdout);
  std::thread manager_thread(joint_manager_task, std::ref(manager), std::ref(clock), std::ref(state));
  std::thread handler_thread(handler_task, std::ref(handler), std::ref(scenario), std::cref(options), std::ref(clock),
                             std::ref(state));
  static hal::MonotonicClock operator_clock;
  std::thread parser_thread(parser_task, std::ref(parser), std::ref(operator_clock), std::ref(state));
  std::thread socket_thread;
  if (operator_port) socket_thread = std::thread(socket_task, std::ref(socket), std::ref(operator_clock), std::ref(state));
  // The two RC tasks compute every period; only the Motion owner's references reach the joints.
  RcTaskSettings rescue_settings = default_rc_task_settings(RcTaskId::rescue);
  if (options.scenario.rescue_motion) rescue_settings.motion.phase_s = options.scenario.motion_phase_s;
  static RcTask rc_rescue(g_links, rescue_settings);
  static RcTask rc_teleop(g_links, default_rc_task_settings(RcTaskId::teleop));
  std::thread rescue_thread(rc_task_thread, std::ref(rc_rescue), std::ref(clock), std::ref(state));
  std::thread teleop_thread(rc_task_thread, std::ref(rc_teleop), std::ref(clock), std::ref(state));
  const int task_count = operator_port ? 6 : 5;
  // Init is complete once every task is past its set-up (thread start-up allocates).
  hal::MonotonicClock logger_clock;
  while (state.tasks_started.load(std::memory_order_acquire) < task_count) {
    logger_clock.sleep_until(logger_clock.now() + hal::kNsPerMs);
  }
  declare_init_complete(HeapGuardMode::count);

  // 5. Logger and operator: print what the tasks report; "initialize robot" once in OP.
  bool op_announced = false;
  bool scenario_announced = false;
  bool initialized = !(options.initialize || options.scenario.kind != ScenarioKind::none);
  bool clear_sent = to_clear == 0;
  MotionLog motion_log;
  HandlerEvent event{};
  for (;;) {
    const bool done = state.handler_done.load(std::memory_order_acquire);
    if (!scenario_announced && state.scenario_acted.load(std::memory_order_acquire)) {
      scenario_announced = true;
      char names[kJointNamesCapacity];
      format_joint_names(options.scenario.expected_lost, names, sizeof names);
      if (scenario.action_status().ok()) {
        (void)std::printf("[%8.3f s] scenario %s: %s %s (expect %s lost)\n", seconds(scenario.acted_at() - start),
                          options.scenario.name,
                          options.scenario.kind == ScenarioKind::power_cycle    ? "power-cycle the drive of"
                          : options.scenario.kind == ScenarioKind::cable_damage ? "damage 5 frames on the cable into"
                                                                                : "cut the link into",
                          kJoints[options.scenario.cut_joint].name, names);
      } else {
        (void)std::printf("scenario %s: %s\n", options.scenario.name, scenario.action_status().error().what);
      }
    }
    while (handler.pop_event(event)) print_handler_event(event, start);
    print_joint_events(events, event_printer);
    if (!op_announced && state.op.load(std::memory_order_acquire)) {
      op_announced = true;
      (void)std::printf("[%8.3f s] ethercat: network in OP, cycling every 1 ms\n",
                        seconds(state.op_at.load(std::memory_order_relaxed) - start));
    }
    // The DFA takes its steps only for reachable joints: wait until the handler's published values
    // show every joint that is not recorded lost reachable (the first OP cycles may not).
    if (op_announced && !clear_sent && all_reachable(to_clear)) {
      clear_sent = true;
      char names[kJointNamesCapacity];
      format_joint_names(to_clear, names, sizeof names);
      (void)std::printf("[%8.3f s] operator: clear repaired joints %s (then reset)\n", seconds(clock.now() - start), names);
      (void)send_local(protocol::MessageType::clear_joints, to_clear);
    }
    if (op_announced && clear_sent && !initialized && all_reachable(kAllJoints & ~out_of_service)) {
      initialized = true;
      (void)std::printf("[%8.3f s] operator: initialize robot (select mode, set reference, enable)\n",
                        seconds(clock.now() - start));
      (void)send_local(protocol::MessageType::initialize, kAllJoints & ~out_of_service);
      if (options.scenario.rescue_motion) {
        // After the initialize (the parser takes one request at a time): the rescue RC task takes the motion.
        (void)std::printf("[%8.3f s] operator: owner %u (the rescue RC task takes the motion)\n",
                          seconds(clock.now() - start), static_cast<unsigned>(RcTaskId::rescue));
        ControlRequest take;
        take.type = protocol::MessageType::take_owner;
        take.task = static_cast<std::uint8_t>(RcTaskId::rescue);
        if (!g_links.local_requests.try_push(take)) (void)std::printf("operator: request queue full, owner dropped\n");
      }
    }
    print_local_replies(clock.now() - start);
    print_motion_changes(motion_log, clock.now() - start);
    (void)std::fflush(stdout);
    if (g_capture.is_open()) (void)g_capture_queue.drain(g_capture, kCaptureFramesPerLoggerPass);
    if (done) break;
    logger_clock.sleep_until(logger_clock.now() + kLoggerPeriod);
  }
  handler_thread.join();
  // The drives are off: the joint manager's Enabled DFAs follow (Enabled -> Ready) in its last step.
  // Which joints are Enabled comes from its published demand (its own state belongs to its thread).
  RobotDemand demand{};
  JointMask enabled = 0;
  if (g_links.demand.try_read(demand)) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if (demand[j].enable) enabled |= joint_bit(j);
    }
  }
  // Through the parser, the joint handle queue's only producer; its answer comes within its timeout.
  if (enabled != 0 && send_local(protocol::MessageType::disable, enabled)) {
    const hal::Nanoseconds give_up = logger_clock.now() + MessageParser::kReplyTimeout + 100 * hal::kNsPerMs;
    while (g_links.local_replies.empty_approx() && logger_clock.now() < give_up) {
      logger_clock.sleep_until(logger_clock.now() + hal::kNsPerMs);
    }
    print_local_replies(clock.now() - start);
  }
  state.operator_stop.store(true, std::memory_order_release);
  parser_thread.join();
  if (socket_thread.joinable()) socket_thread.join();
  state.rc_stop.store(true, std::memory_order_release);
  rescue_thread.join();
  teleop_thread.join();
  state.manager_stop.store(true, std::memory_order_release);
  manager_thread.join();
  while (handler.pop_event(event)) print_handler_event(event, start);
  print_joint_events(events, event_printer);

  // 6. What happened.
  const HeapGuardCounters heap = heap_guard_counters();
  const JointMask lost = manager.lost_joints();
  const std::uint64_t healthy_missed = handler.missed_cycles(kAllJoints & ~lost);
  char lost_names[kJointNamesCapacity];
  format_joint_names(lost, lost_names, sizeof lost_names);
  if (stop_signal() != 0) print_stop_line(state, handler.drives_disabled(), manager.file_dirty());
  const std::uint64_t skipped = handler.bus().master().skipped_periods();
  (void)std::printf("rescue-motion run: %" PRIu64 " cycles; healthy joints missed %" PRIu64
                    " cycles; frames late or lost: %" PRIu64 "; late periods: %" PRIu64 " (%" PRIu64
                    " not run); lost joints: %s; robot %s\n",
                    state.cycles.load(), healthy_missed, handler.frames_missing(), state.late_periods.load(), skipped,
                    lost_names, fsm::to_string(manager.summary().condition));
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::uint64_t m = handler.missed_cycles(joint_bit(j) & ~lost);
    if (m != 0) (void)std::printf("rescue-motion run: %s missed %" PRIu64 " cycles\n", kJoints[j].name, m);
  }
  (void)std::printf("rescue-motion run: heap allocations after init: %" PRIu64 "\n", heap.allocations);
  const SocketCounters& counted = socket.counters();
  if (operator_port) {
    (void)std::printf("rescue-motion run: datagrams %" PRIu64 ", accepted %" PRIu64, counted.datagrams, counted.accepted);
    for (std::size_t i = 0; i < protocol::kRejectionCount; ++i) {
      (void)std::printf(", %s %" PRIu64, protocol::to_string(static_cast<protocol::Rejection>(i)), counted.rejected[i]);
    }
    (void)std::printf("\n");
    (void)std::printf("rescue-motion run: socket handler wake-ups %" PRIu64 ", at the budget %" PRIu64
                      ", most datagrams in one wake-up %zu (budget %zu)\n",
                      counted.wakeups, counted.budget_exhausted, socket.max_per_wakeup(), SocketHandler::kBudget);
  }
  if (options.report != nullptr) {
    options.report->cycles = state.cycles.load();
    options.report->healthy_missed = healthy_missed;
    options.report->frames_missing = handler.frames_missing();
    options.report->datagrams = counted.datagrams;
    options.report->accepted = counted.accepted;
    options.report->rejected = counted.rejected;
    options.report->control_port = socket.control_port();
    options.report->sensor_port = socket.sensor_port();
  }
  if (options.timing_out != nullptr) {
    const Status timing = write_task_timing(options.timing_out);
    if (!timing.ok()) return fail("run", "cannot write --timing-out", timing.error());
  }
  if (options.capture_path != nullptr) {
    const Status closed = finish_capture(options.capture_path);
    if (!closed.ok()) return fail("run", "cannot close the capture file", closed.error());
  }

  const int verdict = scenario_verdict(options.scenario, scenario, lost, restored.restored, healthy_missed,
                                       manager.file_dirty(), motion_log, handler.motion_intake().counters());
  if (verdict == 0 && options.scenario.kind != ScenarioKind::none) {
    (void)std::printf("rescue-motion run: scenario %s passed: %s marked lost, recorded in %s/%s\n",
                      options.scenario.name, lost_names, dir.value().path.c_str(),
                      ErrorJointsFileStorage::kFileName);
  }
  RunSummary summary;
  summary.cycles = state.cycles.load();
  summary.heap_allocations = heap.allocations;
  summary.lost = lost;
  summary.socket = operator_port ? &counted : nullptr;
  summary.intake = handler.motion_intake().counters();
  summary.rescue_phase_reached = motion_log.rescue_phase_reached;
  print_run_summary(summary);
  if (verdict != 0) return verdict;
  return robot_exit(manager.summary().condition);
}

}  // namespace rescue::app
