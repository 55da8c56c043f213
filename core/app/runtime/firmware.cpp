// run_firmware (firmware.hpp): the start-up sequence of `rescue-motion run` and the wiring of the tasks'
// objects; the runner's other pieces are in this folder (docs/firmware.md, "Code").
#include "core/app/runtime/firmware.hpp"

#include <pthread.h>
#include <sys/stat.h>

#include <cinttypes>
#include <cstdio>

#include "core/app/config/build_info.hpp"
#include "core/app/config/command_line.hpp"
#include "core/app/config/task_table.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/replay_window.hpp"
#include "core/app/runtime/instance_setup.hpp"
#include "core/app/runtime/nic_factory.hpp"
#include "core/app/runtime/operator_side.hpp"
#include "core/app/runtime/run_context.hpp"
#include "core/app/runtime/run_control_check.hpp"
#include "core/app/runtime/run_log.hpp"
#include "core/app/runtime/run_report.hpp"
#include "core/app/runtime/sii_cache_file.hpp"
#include "core/app/runtime/startup_log.hpp"
#include "core/app/runtime/task_ports.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "core/app/runtime/task_modes.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/app/shm/segment_layout.hpp"
#include "core/app/sim/simulated_robot_instance.hpp"
#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/error_joints_worker.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_event_printer.hpp"
#include "core/app/tasks/joint_event_queue.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/message_parser.hpp"
#include "core/app/tasks/rescue_task.hpp"
#include "core/app/tasks/teleop_task.hpp"
#include "core/app/tasks/repaired_joints.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "core/memory/heap_guard.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "ecat/capture/capture_tap.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "hal/files/state_dir.hpp"
#include "hal/files/trusted_file.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {

using namespace runner;  // NOLINT(google-build-using-namespace): the runner's pieces (run_context.hpp)

namespace {

// start_task_timing() on a thread of its own with a 64 KiB stack (pthread: std::thread cannot size
// its stack); if the thread cannot be created, join() calibrates on the caller's thread.
class TaskTimingCalibration {
 public:
  TaskTimingCalibration() noexcept {
    pthread_attr_t attr;
    started_ = pthread_attr_init(&attr) == 0;
    if (!started_) return;
    started_ = pthread_attr_setstacksize(&attr, kStackBytes) == 0 && pthread_create(&thread_, &attr, &run, nullptr) == 0;
    (void)pthread_attr_destroy(&attr);
  }
  TaskTimingCalibration(const TaskTimingCalibration&) = delete;
  TaskTimingCalibration& operator=(const TaskTimingCalibration&) = delete;
  TaskTimingCalibration(TaskTimingCalibration&&) = delete;
  TaskTimingCalibration& operator=(TaskTimingCalibration&&) = delete;
  ~TaskTimingCalibration() { join(); }
  void join() noexcept {
    if (joined_) return;
    joined_ = true;
    if (!started_ || pthread_join(thread_, nullptr) != 0) start_task_timing();
  }

 private:
  static constexpr std::size_t kStackBytes = std::size_t{64} * 1024;
  static void* run(void* /*unused*/) noexcept {
    start_task_timing();
    return nullptr;
  }
  pthread_t thread_{};
  bool started_{false};
  bool joined_{false};
};


// What the steps of run_firmware hand on to the next one. The objects the tasks run on are the
// steps' function-local statics (a forked task process finds them at the same addresses); this only
// points at them.
struct StartUp {
  const FirmwareOptions& options;
  hal::SystemWallClock& wall_clock;
  JointEventQueue& events;             // the joint manager's sink; a logger prints (never its real-time thread)
  JointEventPrinter& event_printer;
  hal::StateDir dir{};
  TaskPorts* ports{nullptr};
  ErrorJointsStorageWorker* storage_worker{nullptr};
  JointManager* manager{nullptr};
  MessageParser* parser{nullptr};
  protocol::ReplayWindow* replay{nullptr};
  SocketHandler* socket{nullptr};
  bool operator_port{false};
  hal::Nic* nic{nullptr};
  hal::Nic* ring_nic{nullptr};  // --ring-nic: the master's second port (cable redundancy)
  hal::Clock* clock{nullptr};
  hal::Nanoseconds start{0};
  RestoreReport restored{};
  JointMask to_clear{0};
  JointMask out_of_service{0};
  drivers::JointBus* bus{nullptr};
};

// The simulated segment the scenario's faults act on: the ring robot's with --ring-nic sim, nullptr
// on a real NIC (the faults are then the simulator's commands on its own interface).
drivers::SimulatedSegment* scenario_segment(const FirmwareOptions& options, hal::Nanoseconds now) noexcept {
  if (options.nic.kind != NicKind::sim) return nullptr;
  const bool ring = options.ring_nic_text != nullptr && options.ring_nic.kind == NicKind::sim;
  return ring ? &simulated_ring_robot(now).segment() : &simulated_robot(now).segment();
}

// Step 1: the state directory (ours or root's, writable by nobody else: docs/security.md
// "StrictModes"), --timing-out checked now rather than after the run, the instance locks and the
// shared-memory segment.
int open_state_directory(StartUp& up) noexcept {
  const FirmwareOptions& options = up.options;
  const Result<hal::StateDir> dir = hal::resolve_state_dir(options.state_dir);
  if (!dir.ok()) return fail("run", "cannot use the state directory", dir.error());
  up.dir = dir.value();
  (void)std::printf("rescue-motion run: nic %s, scenario %s, state directory %s (%s)\n", options.nic_text,
                    options.scenario.name, up.dir.path.c_str(), up.dir.source);
  hal::FileProblem dir_problem;
  if (!hal::check_trusted_directory(up.dir.path.c_str(), dir_problem).ok()) {
    (void)std::fprintf(stderr, "rescue-motion run: state directory refused: %s\n", dir_problem.c_str());
    return 1;
  }
  if (options.timing_out != nullptr) {
    // A FIFO or a file given as the directory, another user's link on its path or a directory others
    // may write fails at once (written by the same check at the end).
    hal::FileProblem timing_problem;
    if (!hal::open_trusted_directory(options.timing_out, hal::DirectoryUse::output, timing_problem).ok()) {
      (void)std::fprintf(stderr, "rescue-motion run: --timing-out: %s (give an existing directory of your own)\n",
                         timing_problem.c_str());
      return 1;
    }
  }
  const int lock_status = take_instance_locks(options, up.dir.path.c_str());
  if (lock_status != 0) return lock_status;
  return create_segment(options, up.dir.path.c_str());
}

// Step 2: every task's ports over the segment's TaskLinks (task_ports.hpp: each task sees only the
// queues and seqlocks it uses, at the end it uses them), the joint manager with the error-joints
// file's storage worker (a normal-priority thread of its process: one request in flight), and the
// message parser (the joint handle queue's only producer).
void build_joint_side(StartUp& up) noexcept {
  static TaskPorts ports(shared_links());
  static ErrorJointsFileStorage storage(up.dir.path.c_str());
  static ErrorJointsStorageWorker storage_worker(ports.storage_worker_requests(), ports.storage_worker_results(), storage);
  static JointManager manager(ports.joint_manager(storage, up.wall_clock, up.events));
  manager.set_auto_clear_power_cycled(up.options.auto_clear_power_cycled);
  static MessageParser parser(ports.message_parser());
  up.ports = &ports;
  up.storage_worker = &storage_worker;
  up.manager = &manager;
  up.parser = &parser;
}

// The operator's key: --key, else the state directory's operator.key. A missing default key closes
// the operator's ports (said once); any other problem refuses to start.
int load_operator_key(const StartUp& up, hal::PathBuffer& key_path, Result<protocol::Key>& key) noexcept {
  const FirmwareOptions& options = up.options;
  if (options.key_path != nullptr) {
    (void)std::snprintf(key_path.text.data(), key_path.text.size(), "%s", options.key_path);
  } else {
    const Result<hal::PathBuffer> joined = hal::join_path(up.dir.path.c_str(), "operator.key");
    if (!joined.ok()) return fail("run", "key file path", joined.error());
    key_path = joined.value();
  }
  hal::FileProblem key_problem;
  key = protocol::load_key_file(key_path.c_str(), key_problem);
  if (key.ok()) return 0;
  if (options.key_path != nullptr || key.error().code != Errc::not_found) {
    (void)std::fprintf(stderr, "rescue-motion run: key file refused: %s\n", key_problem.c_str());
    return 1;
  }
  (void)std::printf("rescue-motion run: no key file %s: operator and sensor ports closed "
                    "(create one with: rescue-motion ctl keygen --key %s)\n",
                    key_path.c_str(), key_path.c_str());
  return 0;
}

// Step 3: the operator's path in: with a key, the socket handler on its UDP ports.
int open_operator_side(StartUp& up) noexcept {
  const FirmwareOptions& options = up.options;
  if (!protocol::init_crypto().ok()) return fail("run", "libsodium could not be initialised");
  hal::PathBuffer key_path;
  Result<protocol::Key> key = make_error(Errc::not_found, "not loaded");
  const int key_status = load_operator_key(up, key_path, key);
  if (key_status != 0) return key_status;
  up.operator_port = key.ok();
  static protocol::ReplayWindow replay;
  SocketHandlerPorts socket_ports = up.ports->socket_handler();
  socket_ports.stale_after = options.task_silent_after;
  socket_ports.rc_tasks = kRcTasksRun;
  static protocol::VersionPayload version;
  protocol::set_text(version.program, build_program_version());
  version.layout_version = TaskLinks::kLayoutVersion;
  version.layout_hash = shm::kLayoutHash;
  protocol::set_text(version.build_type, build_type());
  socket_ports.version = &version;
  static SocketHandler socket(socket_ports, up.operator_port ? key.value() : protocol::Key{}, replay, up.wall_clock,
                              options.robot_id);
  up.replay = &replay;
  up.socket = &socket;
  if (!up.operator_port) return 0;
  // A new epoch: every datagram made before this start is refused (docs/protocol.md "Replay protection").
  replay.begin_epoch(protocol::new_epoch());
  SocketHandlerOptions socket_options;
  socket_options.listen = options.listen;
  socket_options.control_port = options.control_port;
  socket_options.sensor_port = options.sensor_port;
  const Status opened_ports = socket.open(socket_options);
  if (!opened_ports.ok()) return fail("run", "cannot open the UDP ports", opened_ports.error());
  (void)std::printf("rescue-motion run: operator control port %s:%u, sensor port %s:%u (key %s, robot id %u)\n",
                    options.listen, static_cast<unsigned>(socket.control_port()), options.listen,
                    static_cast<unsigned>(socket.sensor_port()), key_path.c_str(), static_cast<unsigned>(options.robot_id));
  return 0;
}

// Step 4: the NIC, then the joints the error-joints file records lost, and the operator's clear of
// repaired joints (they must answer at bring-up; the file changes only once they do).
int open_nic_and_restore_joints(StartUp& up) noexcept {
  const FirmwareOptions& options = up.options;
  static SelectedNic selected;
  const Status opened = selected.open(options.nic);
  if (!opened.ok()) return fail_nic("run", options.nic_text, opened.error());
  if (options.ring_nic_text != nullptr) {
    const Status ring = selected.open_ring(options.ring_nic);
    if (!ring.ok()) return fail_nic("run", options.ring_nic_text, ring.error());
    up.ring_nic = selected.ring_nic();
  }
  up.nic = selected.nic();
  up.clock = &up.nic->clock();
  up.start = up.clock->now();
  up.event_printer.set_origin(up.start);
  up.restored = up.manager->restore(up.clock->now());
  print_joint_events(up.events, up.event_printer);
  print_restored(up.restored.restored);
  const RepairedJointsPlan repaired = plan_repaired_joints(options.clear_joints, up.restored.restored);
  if (!announce_repaired_joints(repaired)) return 1;
  up.to_clear = repaired.to_clear;
  up.out_of_service = repaired.out_of_service;
  print_restore_problems(up.restored, up.dir.path.c_str());
  return 0;
}

// The master's options for `run`: stoppable by SIGINT/SIGTERM, online recovery on, and never silent
// while it waits for the first frame to come back (a line about once a second).
ecat::MasterOptions run_master_options(const FirmwareOptions& options) noexcept {
  ecat::MasterOptions master_options;
  master_options.stop_requested = []() noexcept { return stop_signal() != 0; };
  master_options.online_recovery = true;  // returning slaves back to OP while cycling (docs/master.md)
  master_options.first_contact_timeout = options.first_contact_limit;
  master_options.waiting = [](const ecat::BringUpWait& wait, void*) noexcept {
    if (wait.limit > 0) {
      (void)std::printf("rescue-motion run: waiting for first contact: no EtherCAT frame came back yet (%u BRDs in %.1f s); "
                        "giving up after %.1f s\n",
                        static_cast<unsigned>(wait.frames), seconds(wait.waited), seconds(wait.limit));
    } else {
      (void)std::printf("rescue-motion run: waiting for first contact: no EtherCAT frame came back yet (%u BRDs in %.1f s); "
                        "trying until stopped\n",
                        static_cast<unsigned>(wait.frames), seconds(wait.waited));
    }
    (void)std::fflush(stdout);
  };
  return master_options;
}

// --capture: opened before the bring-up, whose frames this thread writes directly.
int open_capture(const StartUp& up) noexcept {
  if (up.options.capture_path == nullptr) return 0;
  ecat::CaptureWriterOptions capture_options;
  capture_options.timestamp_offset = ecat::unix_time_offset(*up.clock);
  const Status capture = g_run.capture.open(up.options.capture_path, capture_options);
  if (!capture.ok()) {
    (void)std::fprintf(stderr, "rescue-motion run: --capture: %s\n", g_run.capture.problem().c_str());
    return fail("run", "cannot open the capture file", capture.error());
  }
  up.bus->master().set_tap(ecat::capture_tap, &g_run.capture);
  return 0;
}

// What the bring-up found, once it succeeded, and the SII cache saved when a device was new or
// changed (a durable write of about 30 KiB before the tasks start).
void report_bring_up(const StartUp& up, const ecat::SiiCache& sii_cache) noexcept {
  const ecat::BringUpReport& bring_up = up.bus->master().report();
  (void)std::printf("rescue-motion run: %u slaves found, SAFE-OP after %.3f s, distributed clocks within %u ns\n",
                    static_cast<unsigned>(bring_up.slaves_counted), seconds(bring_up.safe_op_at - bring_up.started_at),
                    bring_up.dc_max_difference_ns);
  if (bring_up.pdo_rewritten != 0) {
    char rewritten[kJointNamesCapacity];
    format_joint_names(drivers::joints_of_slaves(bring_up.pdo_rewritten), rewritten, sizeof rewritten);
    (void)std::printf("rescue-motion run: PDO mapping rewritten (it differed from the plan): %s (%u SDO writes)\n", rewritten,
                      static_cast<unsigned>(bring_up.pdo_writes));
  }
  if (!sii_cache.changed()) return;
  const Status saved = save_sii_cache(up.dir.path.c_str(), sii_cache);
  if (!saved.ok()) {
    (void)std::printf("rescue-motion run: SII cache not saved to %s/%s: %s\n", up.dir.path.c_str(), kSiiCacheFileName,
                      saved.error().what);
  }
}

// Step 5: the network. From here to the bring-up's end (memory locked, the SII cache read, the
// bring-up itself) this thread runs as the EtherCAT handler will, at its priority on its CPU, so that
// a busy host does not stretch it (every bring-up frame waits for the one before; the locking
// populates ~20 MiB); then it is given back its normal scheduling: once it has forked the handler's
// process (which so starts at the handler's priority), before it forks the other tasks.
int bring_up_network(StartUp& up, TaskTimingCalibration& calibration) noexcept {
  const FirmwareOptions& options = up.options;
  static hal::SchedulingState normal_scheduling{};
  const Result<hal::SchedulingState> normal = hal::save_scheduling();
  const int handler_priority = runner_priority(TaskId::ethercat_handler);
  const bool raised = normal.ok() && handler_priority > 0 && hal::set_fifo_priority(handler_priority).ok();
  if (raised) (void)hal::pin_to_cpu(table_cpu_on_this_machine(task_spec(TaskId::ethercat_handler).cpu));  // may be refused: any CPU then
  // The machine: memory locked and prefaulted once (each task sets its own priority and CPU).
  hal::RtConfig process_rt;
  process_rt.lock_memory = true;
  const hal::RtReport rt = hal::apply_rt_config(process_rt);
  if (!rt.fully_applied()) rt.print(stdout);

  // With a ring NIC the robot is cabled as the ring configuration's line (docs/redundancy.md).
  static drivers::JointBus bus(*up.nic, up.ring_nic != nullptr ? drivers::kRobotRingNetworkPlan : drivers::kRobotNetworkPlan);
  up.bus = &bus;
  if (up.ring_nic != nullptr) bus.master().use_ring(*up.ring_nic);  // docs/redundancy.md
  const int capture_status = open_capture(up);
  if (capture_status != 0) return capture_status;
  ecat::MasterOptions master_options = run_master_options(options);
  // Whole SII images of the devices seen at earlier starts (docs/master.md "SII cache"): each slave's
  // identity and serial number are read every time, the rest comes from the cache when they match.
  static ecat::SiiCache sii_cache;
  const Status cache_loaded = load_sii_cache(up.dir.path.c_str(), sii_cache);
  if (!cache_loaded.ok() && cache_loaded.error().code != Errc::not_found) {
    (void)std::printf("rescue-motion run: SII cache %s/%s ignored (%s): every slave's SII is read whole\n",
                      up.dir.path.c_str(), kSiiCacheFileName, cache_loaded.error().what);
  }
  master_options.sii_cache = &sii_cache;
  (void)std::printf("rescue-motion run: bringing the EtherCAT network up\n");
  (void)std::fflush(stdout);
  if (options.scenario.mapping_fault) {
    // half-mapped, foreign-mapping: the drive's mapping is wrong before the master first sees it.
    ScenarioRunner first(options.scenario, scenario_segment(options, up.clock->now()));
    const Status faulted = first.before_bring_up();
    if (!faulted.ok()) return fail("run", "the scenario's mapping fault could not be applied", faulted.error());
  }
  const Status brought_up = bus.bring_up(master_options, up.out_of_service);
  calibration.join();
  if (raised && brought_up.ok() && g_run.task_processes) {
    normal_scheduling = normal.value();
    g_run.start_up_scheduling = &normal_scheduling;  // given back once the handler is forked (task_processes.cpp)
  } else if (raised && !hal::restore_scheduling(normal.value()).ok()) {
    return fail("run", "cannot give the start-up thread back its normal scheduling after bring-up");
  }
  if (!brought_up.ok() && stop_signal() != 0) return stopped_in_bring_up(bus, options);
  if (!brought_up.ok()) {
    if (up.to_clear != 0) {
      (void)std::fprintf(stderr, "rescue-motion run: the error-joints file is unchanged: the joints declared repaired "
                                 "must answer at bring-up\n");
    }
    return report_bring_up_failure(bus);
  }
  report_bring_up(up, sii_cache);
  return 0;
}

// Step 6: the tasks, as processes (the default) or threads; from now on the handler only queues
// captured frames. The two RC tasks compute every period; only the Motion owner's references reach
// the joints.
int run_tasks(const StartUp& up, OperatorSide& operator_side) noexcept {
  const FirmwareOptions& options = up.options;
  if (!g_run.task_processes && !options.threads) {
    (void)std::printf("rescue-motion run: --timing-out: the tasks run as threads of one process (their recorders are "
                      "written together)\n");
  }
  if (g_run.capture.is_open()) up.bus->master().set_tap(ecat::capture_queue_tap, &g_run.capture_queue);
  drivers::SimulatedSegment* segment = scenario_segment(options, up.clock->now());
  static EthercatHandler handler(*up.bus, up.ports->ethercat_handler(), up.restored.restored);
  static ScenarioRunner scenario(options.scenario, segment);
  static hal::MonotonicClock operator_clock;
  RescueTaskSettings rescue_settings = default_rescue_task_settings();
  if (options.scenario.rescue_motion) rescue_settings.motion.phase_s = options.scenario.motion_phase_s;
  static RescueTask rc_rescue(up.ports->rc_task(RcTaskId::rescue), rescue_settings);
  static TeleopTask rc_teleop(up.ports->rc_task(RcTaskId::teleop), default_teleop_task_settings());
  g_run.tasks = TaskSet{&handler,      &scenario,        up.manager,       up.parser,          up.socket,
                        &rc_rescue,    &rc_teleop,       up.replay,          &up.wall_clock,     up.clock,
                        &operator_clock, &options,       up.operator_port,   up.start,           &up.events,
                        &up.event_printer, up.storage_worker, up.ports};
  return g_run.task_processes ? run_task_processes(operator_side) : run_task_threads(operator_side);
}

// The scenario's verdict line (a failed one is printed by scenario_verdict).
void print_scenario_passed(const StartUp& up, JointMask lost, JointMask lost_since_start) noexcept {
  const FirmwareOptions& options = up.options;
  char lost_names[kJointNamesCapacity];
  format_joint_names(lost | lost_since_start, lost_names, sizeof lost_names);
  const JointMask cleared = lost_since_start & ~lost;
  char cleared_names[kJointNamesCapacity];
  format_joint_names(cleared, cleared_names, sizeof cleared_names);
  if ((lost | lost_since_start) == 0) {
    // Nothing lost, nothing written: no file to name (cable-damage, flaky-cable).
    (void)std::printf("rescue-motion run: scenario %s passed: no joint marked lost, nothing recorded\n", options.scenario.name);
    return;
  }
  (void)std::printf("rescue-motion run: scenario %s passed: %s marked lost, recorded in %s/%s%s%s\n", options.scenario.name,
                    lost_names, up.dir.path.c_str(), ErrorJointsFileStorage::kFileName, cleared != 0 ? "; cleared since: " : "",
                    cleared != 0 ? cleared_names : "");
}

// With a ring NIC: the ring's state at the end, its breaks and repairs, and the exchanges sent
// again after a repair in flight (docs/redundancy.md). The handler leaves them in the run control
// when it ends, as a thread or as a process of its own; "n/a" when it did not end by itself.
void print_ring_state(const StartUp& up, const RunControl& state) noexcept {
  if (up.ring_nic == nullptr) return;
  if (!state.handler_done.load(std::memory_order_acquire)) {
    (void)std::printf("ring_state: n/a (the EtherCAT handler did not report its final figures; its ring lines are above)\n");
    (void)std::printf("ring_repeats: n/a\n");
    return;
  }
  const auto ring_state = static_cast<ecat::RingState>(state.ring_state.load(std::memory_order_relaxed));
  (void)std::printf("ring_state: %s (breaks %" PRIu64 ", repairs %" PRIu64 ")\n", ecat::to_string(ring_state),
                    state.ring_breaks.load(std::memory_order_relaxed), state.ring_repairs.load(std::memory_order_relaxed));
  (void)std::printf("ring_repeats: %" PRIu64 " (exchanges sent again: the ring closed while a frame was in flight)\n",
                    state.ring_repeats.load(std::memory_order_relaxed));
}

// Step 7: what happened, and the exit status (docs/firmware.md "Exit status").
int report_run(const StartUp& up, int tasks_status, const OperatorSide& operator_side) noexcept {
  const FirmwareOptions& options = up.options;
  RunControl& state = run_control();
  // The figures come from the segment: damaged ones are neither printed nor judged.
  const char* damaged = run_control_damage(state);
  if (damaged != nullptr) {
    (void)std::printf("rescue-motion run: the tasks' shared state is damaged (%s): the run's figures are not printed "
                      "or judged\n",
                      damaged);
    (void)std::fprintf(stderr, "rescue-motion run: shared segment damaged (%s); exit status %d\n", damaged,
                       kExitSegmentDamaged);
    return kExitSegmentDamaged;
  }
  const JointMask lost = state.lost_joints.load();
  const auto condition = static_cast<fsm::RobotCondition>(state.condition.load());
  (void)print_run_figures(options, *up.socket);
  if (tasks_status != 0) return tasks_status;
  if (!state.op.load(std::memory_order_acquire) && stop_signal() == 0) {
    // The run ended (--duration, a scenario) without the network ever in OP: not an idle robot.
    (void)std::printf("rescue-motion run: FAILED: the network never reached OP (the slave that did not follow is named "
                      "above)\n");
    return 1;
  }
  if (options.timing_out != nullptr) {
    const Status timing = write_task_timing(options.timing_out);
    if (!timing.ok()) return fail("run", "cannot write --timing-out", timing.error());
  }
  const int verdict = scenario_verdict(options.scenario, state, lost, up.restored.restored, options.auto_clear_power_cycled,
                                       operator_side.motion.rescue_phase_reached);
  if (verdict == 0 && options.scenario.kind != ScenarioKind::none) print_scenario_passed(up, lost, state.lost_since_start.load());
  SocketCounters counted{};
  (void)shared_links().socket_counters.try_read(counted);
  RunSummary summary;
  summary.cycles = state.cycles.load();
  summary.heap_allocations = heap_guard_counters().allocations;
  summary.lost = lost;
  summary.socket = up.operator_port ? &counted : nullptr;
  summary.intake.owned_periods = state.intake_owned_periods.load();
  summary.intake.used_periods = state.intake_used_periods.load();
  summary.intake.misses = state.intake_misses.load();
  summary.intake.releases = state.intake_releases.load();
  summary.rescue_phase_reached = operator_side.motion.rescue_phase_reached;
  summary.processes = g_run.task_processes;
  summary.start = up.start;
  summary.bring_up = &up.bus->master().report();
  summary.supervisor_damaged_beats = liveness_damaged_beats();
  print_run_summary(summary);
  print_ring_state(up, state);
  const int limits = sent_joint_limits_exit(state);
  if (verdict != 0) return verdict;
  if (limits != 0) return limits;
  return robot_exit(condition);
}

}  // namespace

// The start-up sequence in its named steps, top to bottom as docs/firmware.md and docs/tasks.md
// describe it: the state directory (the error-joints file before the network: design brief
// section 6), the joint side, the operator side, the NIC and the joints restored, the network, the
// tasks, the report.
int run_firmware(const FirmwareOptions& options) noexcept {
  static hal::SystemWallClock wall_clock;
  static JointEventQueue events;
  static JointEventPrinter event_printer(stdout, "joint-manager: ");
  StartUp up{options, wall_clock, events, event_printer};

  // --timing-out writes the handler's and the joint manager's recorders together: one process's memory.
  g_run.task_processes = !options.threads && options.timing_out == nullptr;
  if (g_run.task_processes) {
    // Several processes write to one stdout: whole lines, each in one write (a pipe keeps writes of
    // up to PIPE_BUF bytes whole), so their lines never mix. Set before the first output.
    static char stdout_buffer[4096];
    (void)std::setvbuf(stdout, stdout_buffer, _IOLBF, sizeof stdout_buffer);
  }
  // SIGINT/SIGTERM from the first instant: every phase (bring-up included) polls the flag and stops
  // cleanly, with one line saying where.
  if (!install_stop_handlers()) return fail("run", "cannot install SIGINT/SIGTERM handlers");
  // The tasks' TSC timer is calibrated (two readings 20 ms apart, hal/time/tsc_timer.hpp) on another
  // thread from here until the bring-up ends: time to OP does not wait for it. Its stack is small:
  // once memory is locked, every page of a thread's stack is populated (8 MiB by default, ~2 ms).
  TaskTimingCalibration calibration;

  int status = open_state_directory(up);
  if (status != 0) return status;
  build_joint_side(up);
  status = open_operator_side(up);
  if (status == 0) status = open_nic_and_restore_joints(up);
  if (status == 0) status = bring_up_network(up, calibration);
  if (status != 0) return status;
  OperatorSide operator_side{up.to_clear, up.out_of_service, up.to_clear == 0,
                             !(options.initialize || options.scenario.kind != ScenarioKind::none), false, MotionLog{}};
  const int tasks_status = run_tasks(up, operator_side);
  if (tasks_status == kExitSegmentDamaged) return tasks_status;  // its figures are garbage: none printed
  return report_run(up, tasks_status, operator_side);
}

}  // namespace rescue::app

