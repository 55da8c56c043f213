#include "core/app/runtime/firmware.hpp"

#include <unistd.h>

#include <atomic>
#include <cinttypes>
#include <cstdio>
#include <thread>

#include "core/app/cli/cli.hpp"
#include "core/app/config/firmware_config.hpp"
#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_event_printer.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/links/joint_sample_source.hpp"
#include "core/app/runtime/nic_factory.hpp"
#include "core/app/control/predefined_messages.hpp"
#include "core/app/control/repaired_joints.hpp"
#include "core/app/sim/simulated_robot_instance.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/app/links/task_links.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "ecat/capture/capture_queue.hpp"
#include "ecat/capture/capture_tap.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/files/state_dir.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {
namespace {

// Priorities, CPUs and periods: the task table (runtime/task_table.hpp, config/firmware_config.hpp).
constexpr int kHandlerPriority = config::kEthercatHandlerPriority;
constexpr int kJointManagerPriority = config::kJointManagerPriority;
constexpr int kHandlerCpu = config::kEthercatHandlerCpu;
constexpr int kJointManagerCpu = config::kJointManagerCpu;
constexpr hal::Nanoseconds kJointManagerPeriod = config::kJointManagerPeriodNs;
constexpr hal::Nanoseconds kLoggerPeriod = config::kLoggerPeriodNs;
constexpr hal::Nanoseconds kDisableTimeout = config::kDisableTimeoutNs;
// A scenario without --duration runs this long after it acted, then stops.
constexpr hal::Nanoseconds kScenarioRunOn = config::kScenarioRunOnNs;

// Everything the tasks use, in static storage: taken once at start-up, never from the heap.
TaskLinks g_links;
ecat::CaptureWriter g_capture;
// The handler's tap only copies frames into this queue; the logger thread writes them (the disk
// may block, the 1 ms cycle must not).
ecat::CaptureQueue g_capture_queue;
constexpr std::size_t kCaptureFramesPerLoggerPass = 256;

// The CPU a task asks for, or the machine's last one when it has fewer (announced by the RT report).
int cpu_for(int wanted) noexcept {
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  if (online <= 0 || wanted < online) return wanted;
  return static_cast<int>(online - 1);
}

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
  std::atomic<int> tasks_started{0};  // tasks past their real-time set-up
};

void print_handler_event(const HandlerEvent& e, hal::Nanoseconds start) noexcept {
  char names[kJointNamesCapacity];
  format_joint_names(e.joints, names, sizeof names);
  const double t = seconds(e.time - start);
  switch (e.kind) {
    case HandlerEventKind::link_report:
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

void handler_task(EthercatHandler& handler, ScenarioRunner& scenario, const FirmwareOptions& options, hal::Clock& clock,
                  RunState& state) noexcept {
  apply_thread_rt("ethercat", kHandlerPriority, kHandlerCpu);
  state.tasks_started.fetch_add(1, std::memory_order_release);
  const drivers::JointBus& bus = handler.bus();
  const hal::Nanoseconds started = clock.now();
  hal::Nanoseconds stop_at = options.duration > 0 ? started + options.duration : -1;
  hal::Nanoseconds stopping_since = -1;
  TaskTiming& timing = task_timing();
  for (;;) {
    const hal::Nanoseconds release = bus.next_wakeup();
    clock.sleep_until(release);
    const std::uint64_t work_start = timing.timer.start();
    const drivers::JointCycleResult r = handler.cycle();
    const std::uint64_t work_end = timing.timer.stop();
    const hal::Nanoseconds now = clock.now();
    // Woke at now - the work's duration: no extra clock read.
    timing.handler.record(now - timing.timer.to_ns(work_end - work_start) - release, work_start, work_end);
    state.cycles.store(r.cycle, std::memory_order_relaxed);
    const bool op = r.state == ecat::MasterState::op;
    if (op && !state.op.load(std::memory_order_relaxed)) {
      state.op_at.store(now, std::memory_order_relaxed);
      state.op.store(true, std::memory_order_release);
    }
    if (scenario.on_cycle(now, op)) {
      state.scenario_acted.store(true, std::memory_order_release);
      if (options.duration == 0) stop_at = now + kScenarioRunOn;
    }
    if (stopping_since < 0 && (stop_signal() != 0 || (stop_at >= 0 && now >= stop_at))) {
      handler.stop_drives();
      stopping_since = now;
    }
    if (stopping_since >= 0 && (handler.drives_disabled() || now - stopping_since >= kDisableTimeout)) break;
  }
  state.handler_done.store(true, std::memory_order_release);
}

void joint_manager_task(JointManager& manager, hal::Clock& clock, RunState& state) noexcept {
  apply_thread_rt("joint-manager", kJointManagerPriority, kJointManagerCpu);
  state.tasks_started.fetch_add(1, std::memory_order_release);
  hal::Nanoseconds next = clock.now();
  TaskTiming& timing = task_timing();
  while (!state.manager_stop.load(std::memory_order_acquire)) {
    const hal::Nanoseconds woke = clock.now();
    const std::uint64_t work_start = timing.timer.start();
    manager.step(woke);
    timing.manager.record(woke - next, work_start, timing.timer.stop());
    next += kJointManagerPeriod;
    clock.sleep_until(next);
  }
  manager.step(clock.now());  // the last answers and marks
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

int run_firmware(const FirmwareOptions& options) noexcept {
  static hal::SystemWallClock wall_clock;
  static JointEventPrinter events(stdout, "joint-manager: ");
  static RunState state;

  // 1. The error-joints file, before the network (design brief section 6).
  const Result<hal::StateDir> dir = hal::resolve_state_dir(options.state_dir);
  if (!dir.ok()) return fail("run", "cannot use the state directory", dir.error());
  (void)std::printf("rescue-motion run: nic %s, scenario %s, state directory %s (%s)\n", options.nic_text,
                    options.scenario.name, dir.value().path.c_str(), dir.value().source);
  static ErrorJointsFileStorage storage(dir.value().path.c_str());
  static SpscMessageSource<LostJointsReport, TaskLinks::kReportQueueDepth> reports(g_links.lost_reports);
  static SpscMessageSink<JointManagerNotice, TaskLinks::kNoticeQueueDepth> notices(g_links.notices);
  static SpscMessageSource<JointCommand, TaskLinks::kCommandQueueDepth> commands(g_links.joint_commands);
  static SeqlockSampleSource samples(g_links.samples);
  static SeqlockDemandSink demand_sink(g_links.demand);
  static JointManager manager(JointManagerPorts{&reports, &notices, &commands, &samples, &storage, &wall_clock, &events, &demand_sink});
  static SpscMessageSink<JointCommand, TaskLinks::kCommandQueueDepth> parser_out(g_links.joint_commands);

  static SelectedNic selected;
  const Status opened = selected.open(options.nic);
  if (!opened.ok()) return fail_nic("run", options.nic_text, opened.error());
  hal::Nic& nic = *selected.nic();
  hal::Clock& clock = nic.clock();
  const hal::Nanoseconds start = clock.now();
  events.set_origin(start);

  const RestoreReport restored = manager.restore(clock.now());
  if (restored.restored != 0) {
    char names[kJointNamesCapacity];
    format_joint_names(restored.restored, names, sizeof names);
    (void)std::printf("rescue-motion run: restored lost joints %s from the error-joints file before bring-up; "
                      "they stay out of the exchange until an operator clears them\n",
                      names);
  }
  // The operator's clear of repaired joints: they must answer at bring-up; the file changes only
  // once they do (a clear that cannot be confirmed loses nothing).
  const RepairedJointsPlan repaired = plan_repaired_joints(options.clear_joints, restored.restored);
  if (!announce_repaired_joints(repaired)) return 1;
  const JointMask to_clear = repaired.to_clear;
  const JointMask out_of_service = repaired.out_of_service;
  if (!restored.file_status.ok() && restored.file_present) {
    (void)std::printf("rescue-motion run: error-joints file not used: %s (%s); starting safely\n",
                      restored.file_status.error().what, to_string(restored.file_status.error().code));
  }

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

  (void)std::printf("rescue-motion run: bringing the EtherCAT network up\n");
  (void)std::fflush(stdout);
  const Status up = bus.bring_up(master_options, out_of_service);
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
  if (!install_stop_handlers()) return fail("run", "cannot install SIGINT/SIGTERM handlers");
  start_task_timing();
  (void)std::fflush(stdout);
  std::thread manager_thread(joint_manager_task, std::ref(manager), std::ref(clock), std::ref(state));
  std::thread handler_thread(handler_task, std::ref(handler), std::ref(scenario), std::cref(options), std::ref(clock),
                             std::ref(state));
  // Init is complete once both tasks are past their set-up (thread start-up allocates).
  hal::MonotonicClock logger_clock;
  while (state.tasks_started.load(std::memory_order_acquire) < 2) {
    logger_clock.sleep_until(logger_clock.now() + hal::kNsPerMs);
  }
  declare_init_complete(HeapGuardMode::count);

  // 5. Logger and operator: print what the tasks report; "initialize robot" once in OP.
  bool op_announced = false;
  bool scenario_announced = false;
  bool initialized = !(options.initialize || options.scenario.kind != ScenarioKind::none);
  bool clear_sent = to_clear == 0;
  HandlerEvent event{};
  for (;;) {
    const bool done = state.handler_done.load(std::memory_order_acquire);
    if (!scenario_announced && state.scenario_acted.load(std::memory_order_acquire)) {
      scenario_announced = true;
      char names[kJointNamesCapacity];
      format_joint_names(options.scenario.expected_lost, names, sizeof names);
      if (scenario.action_status().ok()) {
        (void)std::printf("[%8.3f s] scenario %s: cut the link into %s (expect %s lost)\n",
                          seconds(scenario.acted_at() - start), options.scenario.name,
                          kJoints[options.scenario.cut_joint].name, names);
      } else {
        (void)std::printf("scenario %s: %s\n", options.scenario.name, scenario.action_status().error().what);
      }
    }
    while (handler.pop_event(event)) print_handler_event(event, start);
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
      for (const JointCommand& command : clear_repaired_joints_commands(to_clear)) {
        if (!parser_out.try_send(command)) (void)std::printf("operator: joint handle queue full, command dropped\n");
      }
    }
    if (op_announced && clear_sent && !initialized && all_reachable(kAllJoints & ~out_of_service)) {
      initialized = true;
      (void)std::printf("[%8.3f s] operator: initialize robot (select mode, set reference, enable)\n",
                        seconds(clock.now() - start));
      for (const JointCommand& command : initialize_robot_commands(kAllJoints & ~out_of_service)) {
        if (!parser_out.try_send(command)) (void)std::printf("operator: joint handle queue full, command dropped\n");
      }
    }
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
  for (const JointCommand& command : stop_robot_commands(enabled)) {
    if (!parser_out.try_send(command)) (void)std::printf("operator: joint handle queue full, command dropped\n");
  }
  state.manager_stop.store(true, std::memory_order_release);
  manager_thread.join();
  while (handler.pop_event(event)) print_handler_event(event, start);

  // 6. What happened.
  const HeapGuardCounters heap = heap_guard_counters();
  const JointMask lost = manager.lost_joints();
  const std::uint64_t healthy_missed = handler.missed_cycles(kAllJoints & ~lost);
  char lost_names[kJointNamesCapacity];
  format_joint_names(lost, lost_names, sizeof lost_names);
  if (stop_signal() != 0) (void)std::printf("rescue-motion run: stopped by signal %d\n", stop_signal());
  (void)std::printf("rescue-motion run: %" PRIu64 " cycles; healthy joints missed %" PRIu64
                    " cycles; frames late or lost: %" PRIu64 "; lost joints: %s; robot %s\n",
                    state.cycles.load(), healthy_missed, handler.frames_missing(), lost_names,
                    fsm::to_string(manager.summary().condition));
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::uint64_t m = handler.missed_cycles(joint_bit(j) & ~lost);
    if (m != 0) (void)std::printf("rescue-motion run: %s missed %" PRIu64 " cycles\n", kJoints[j].name, m);
  }
  (void)std::printf("rescue-motion run: heap allocations after init: %" PRIu64 "\n", heap.allocations);
  if (options.timing_out != nullptr) {
    const Status timing = write_task_timing(options.timing_out);
    if (!timing.ok()) return fail("run", "cannot write --timing-out", timing.error());
  }
  if (options.capture_path != nullptr) {
    const Status closed = finish_capture(options.capture_path);
    if (!closed.ok()) return fail("run", "cannot close the capture file", closed.error());
  }

  if (options.scenario.kind == ScenarioKind::link_cut) {
    if (!scenario.acted() || !scenario.action_status().ok()) return fail("run", "the scenario's link cut did not happen");
    if ((lost & options.scenario.expected_lost) != options.scenario.expected_lost ||
        (lost & ~(options.scenario.expected_lost | restored.restored)) != 0) {
      return fail("run", "the joints marked lost differ from the joints behind the cut");
    }
    if (healthy_missed != 0) return fail("run", "healthy joints missed cycles during the link cut");
    if (manager.file_dirty()) return fail("run", "the error-joints file could not be written");
    (void)std::printf("rescue-motion run: scenario %s passed: %s marked lost, recorded in %s/%s\n",
                      options.scenario.name, lost_names, dir.value().path.c_str(),
                      ErrorJointsFileStorage::kFileName);
  }
  return 0;
}

}  // namespace rescue::app
