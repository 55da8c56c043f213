// The tasks as processes under the supervisor (task_modes.hpp): each task process attaches to the
// segment and runs its loop and its side of the logger; this process supervises, runs the operator's
// side, and stops them in order.
#include "core/app/runtime/task_modes.hpp"
#include "core/app/runtime/task_cpu.hpp"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <thread>
#include <utility>

#include <unistd.h>

#include "core/app/config/command_line.hpp"
#include "core/app/config/task_table.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/runtime/run_context.hpp"
#include "core/app/runtime/run_control_check.hpp"
#include "core/app/runtime/run_log.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "core/app/runtime/supervisor.hpp"
#include "core/app/runtime/task_loops.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/memory/heap_guard.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app::runner {
namespace {

constexpr int kExitTaskDied = 4;  // a critical task process died (docs/tasks.md)
constexpr hal::Nanoseconds kTaskStartLimit = 10 * hal::kNsPerSec;
constexpr hal::Nanoseconds kTaskStopLimit = 5 * hal::kNsPerSec;
constexpr hal::Nanoseconds kAttachLimit = hal::kNsPerSec;

// A task process first checks the segment it inherited is still the one of its name, valid for this
// program (docs/shared-memory.md); 0 when it is, else its exit status.
int attach_task_process(const char* task) noexcept {
  hal::MonotonicClock clock;
  const Result<shm::SegmentAttachment> attached = shm::SegmentAttachment::attach(g_run.segment.name(), clock, kAttachLimit);
  if (!attached.ok()) {
    char line[512];
    (void)shm::describe_segment_error(g_run.segment.name(), attached.error(), line, sizeof line);
    (void)std::fprintf(stderr, "rescue-motion run: %s: %s\n", task, line);
    return 5;
  }
  if (attached.value().segment().header.creator_pid != g_run.segment.segment().header.creator_pid) {
    (void)std::fprintf(stderr, "rescue-motion run: %s: segment %s was replaced by another process; not running\n", task,
                       g_run.segment.name().c_str());
    return 5;
  }
  return 0;
}

// The body of every task process: attach, then the task on its own thread while this one prints
// (stdout is the process's own buffer now) and, in the handler's process, runs its side of the logger.
// The process carries the task's name (`comm`, at most 15 characters: ps, top, chrt tell the task
// processes apart); the task's thread names itself the same (task_loops.cpp).
// The start-up thread's own scheduling back (firmware.cpp kept the handler's for the handler's fork):
// in the supervisor once the handler is forked, and in the handler's process for its logger thread.
Status give_back_start_up_scheduling() noexcept {
  const hal::SchedulingState* normal = g_run.start_up_scheduling;
  g_run.start_up_scheduling = nullptr;
  if (normal == nullptr || hal::restore_scheduling(*normal).ok()) return Status::success();
  return make_error(Errc::io_error, "cannot give the start-up thread back its normal scheduling");
}

int task_process(const char* name, const char* comm, void (*task)() noexcept, void (*log_pass)() noexcept) noexcept {
  (void)hal::name_this_thread(comm);
  const int attached = attach_task_process(name);
  if (attached != 0) return attached;
  declare_init_complete(HeapGuardMode::count);  // each task counts from its own init (TaskHealthProbe)
  std::atomic<bool> finished{false};
  std::thread worker([task, &finished]() noexcept {
    task();
    finished.store(true, std::memory_order_release);
  });
  // The handler's process was forked at the handler's priority and CPU, so its task thread starts at
  // them; this thread, its logger, goes back to normal scheduling (in the other tasks: nothing to do).
  if (!give_back_start_up_scheduling().ok()) (void)std::printf("%s: logger thread left at the start-up priority\n", name);
  hal::MonotonicClock logger_clock;
  while (!finished.load(std::memory_order_acquire)) {
    if (log_pass != nullptr) log_pass();
    (void)std::fflush(stdout);
    logger_clock.sleep_until(logger_clock.now() + kLoggerPeriod);
  }
  worker.join();
  if (log_pass != nullptr) log_pass();
  (void)std::fflush(stdout);
  return 0;
}

int handler_process(void* /*context*/, unsigned /*incarnation*/) noexcept {
  const int status = task_process("ethercat-handler", "ethercat", run_handler, handler_side_pass);
  report_if_never_in_op();
  if (status == 0 && g_run.tasks.options->capture_path != nullptr && !finish_capture(g_run.tasks.options->capture_path).ok()) return 1;
  return status;
}
// The joint manager's process also runs its storage worker, a thread at normal priority created
// here (before the task's thread takes its real-time priority): the file is written off the period.
int manager_process(void* /*context*/, unsigned /*incarnation*/) noexcept {
  g_run.storage_stop.store(false, std::memory_order_relaxed);
  std::thread storage(run_storage_worker);
  const int status = task_process("joint-manager", "joint-manager", run_manager, manager_side_pass);
  g_run.storage_stop.store(true, std::memory_order_release);  // also when the task did not run
  storage.join();
  return status;
}
int parser_process(void* /*context*/, unsigned /*incarnation*/) noexcept {
  return task_process("message-parser", "message-parser", run_parser, nullptr);
}
int socket_process(void* /*context*/, unsigned incarnation) noexcept {
  // A restarted socket handler begins a new epoch: its predecessor's replay windows died with it, so
  // every datagram of the old epoch is refused (docs/protocol.md "Replay protection"). It counts on
  // from the counters its predecessor published.
  if (incarnation > 0) {
    g_run.tasks.replay->begin_epoch(protocol::new_epoch());
    g_run.tasks.socket->resume_counters();
  }
  return task_process("socket-handler", "socket-handler", run_socket, nullptr);
}
// An RC task restarted after a crash starts from its initial state; its owner word, if it held it,
// was released by the handler's intake once its heartbeat stopped (docs/motion-owner.md).
int rc_rescue_process(void* /*context*/, unsigned /*incarnation*/) noexcept {
  return task_process("rc-rescue", "rc-rescue", run_rc_rescue, nullptr);
}
int rc_teleop_process(void* /*context*/, unsigned /*incarnation*/) noexcept {
  return task_process("rc-teleop", "rc-teleop", run_rc_teleop, nullptr);
}

bool handler_finished() noexcept { return run_control().handler_done.load(std::memory_order_acquire); }
bool manager_finished() noexcept { return run_control().manager_done.load(std::memory_order_acquire); }

// The tasks as processes (the default): this process is the supervisor.
struct TaskProcesses {
  std::size_t handler{0};
  std::size_t manager{0};
  std::size_t parser{0};
  std::size_t socket{0};
  std::size_t rc_rescue{0};
  std::size_t rc_teleop{0};
};

Result<TaskProcesses> start_task_processes(Supervisor& supervisor) noexcept {
  TaskProcesses p;
  const Result<std::size_t> handler =
      supervisor.add({"ethercat-handler", TaskCriticality::critical, handler_process, nullptr, handler_finished, SIGTERM});
  const Result<std::size_t> manager =
      supervisor.add({"joint-manager", TaskCriticality::critical, manager_process, nullptr, manager_finished});
  const Result<std::size_t> parser = supervisor.add({"message-parser", TaskCriticality::restartable, parser_process, nullptr});
  if (!handler.ok() || !manager.ok() || !parser.ok()) return make_error(Errc::capacity_exceeded, "supervised tasks");
  p.handler = handler.value();
  p.manager = manager.value();
  p.parser = parser.value();
  if (g_run.tasks.operator_port) {
    const Result<std::size_t> socket = supervisor.add({"socket-handler", TaskCriticality::restartable, socket_process, nullptr});
    if (!socket.ok()) return socket.error();
    p.socket = socket.value();
  }
  const Result<std::size_t> rc_rescue = supervisor.add({"rc-rescue", TaskCriticality::restartable, rc_rescue_process, nullptr});
  const Result<std::size_t> rc_teleop = supervisor.add({"rc-teleop", TaskCriticality::restartable, rc_teleop_process, nullptr});
  if (!rc_rescue.ok() || !rc_teleop.ok()) return make_error(Errc::capacity_exceeded, "supervised tasks");
  p.rc_rescue = rc_rescue.value();
  p.rc_teleop = rc_teleop.value();
  // Start-up order: the task table's (docs/tasks.md).
  const std::pair<TaskId, std::size_t> tasks[] = {{TaskId::joint_manager, p.manager}, {TaskId::ethercat_handler, p.handler},
                                                  {TaskId::message_parser, p.parser}, {TaskId::socket_handler, p.socket},
                                                  {TaskId::rc_tasks, p.rc_rescue},      {TaskId::rc_tasks, p.rc_teleop}};
  int last_order = 0;
  for (const auto& task : tasks) last_order = std::max(last_order, task_spec(task.first).start_order);
  for (int order = 1; order <= last_order; ++order) {
    for (const auto& [id, index] : tasks) {
      if (task_spec(id).start_order != order || (id == TaskId::socket_handler && !g_run.tasks.operator_port)) continue;
      // Only the handler inherits the handler's scheduling: given back before any other is forked.
      if (id != TaskId::ethercat_handler) RESCUE_TRY(give_back_start_up_scheduling());
      RESCUE_TRY(supervisor.start(index));
      if (id == TaskId::ethercat_handler) RESCUE_TRY(give_back_start_up_scheduling());
      (void)std::printf("[%8.3f s] supervisor: started %s (pid %d)\n", supervisor.seconds_now(), supervisor.name(index), static_cast<int>(supervisor.pid(index)));
    }
  }
  RESCUE_TRY(give_back_start_up_scheduling());
  return p;
}

// Stops the operator's tasks, then the joint manager, in that order (docs/tasks.md); the handler
// has ended already.
void stop_operator_and_manager(Supervisor& supervisor, const TaskProcesses& p) noexcept {
  RunControl& state = run_control();
  supervisor.stop_restarting();
  supervisor.expect_exit(p.parser);
  if (g_run.tasks.operator_port) supervisor.expect_exit(p.socket);
  state.operator_stop.store(true, std::memory_order_release);
  (void)supervisor.wait_exit(p.parser, kTaskStopLimit);
  if (g_run.tasks.operator_port) (void)supervisor.wait_exit(p.socket, kTaskStopLimit);
  supervisor.expect_exit(p.rc_rescue);
  supervisor.expect_exit(p.rc_teleop);
  state.rc_stop.store(true, std::memory_order_release);
  (void)supervisor.wait_exit(p.rc_rescue, kTaskStopLimit);
  (void)supervisor.wait_exit(p.rc_teleop, kTaskStopLimit);
  supervisor.expect_exit(p.manager);
  state.manager_stop.store(true, std::memory_order_release);
  (void)supervisor.wait_exit(p.manager, kTaskStopLimit);
  supervisor.signal_all(SIGKILL);  // any that did not stop within its limit (said below)
  for (const std::size_t i : {p.parser, p.socket, p.rc_rescue, p.rc_teleop, p.manager}) {
    if (supervisor.running(i)) (void)std::printf("[%8.3f s] supervisor: %s did not stop within its limit: killed\n", supervisor.seconds_now(), supervisor.name(i));
  }
}

// The segment as the supervisor can check it each pass (docs/shared-memory.md "A damaged segment"):
// its header, written once at creation, still this program's and this process's; the queue it
// consumes (the operator's local replies) within its counters' invariant. Ok when nothing is wrong.
Status segment_damage() noexcept {
  const shm::SharedSegment& segment = g_run.segment.segment();
  RESCUE_TRY(shm::check_header(segment.header, shm::kSegmentSize));
  if (segment.header.creator_pid != static_cast<std::int32_t>(getpid())) {
    return make_error(Errc::mismatch, "creator pid in the header changed",
                      static_cast<std::uint32_t>(segment.header.creator_pid));
  }
  if (segment.links.local_replies.corrupt()) return make_error(Errc::malformed, "the operator replies' queue counters");
  // The run's own words and figures (stop words, masks, states): a value no writer writes.
  const char* run_field = run_control_damage(segment.links.run);
  if (run_field != nullptr) return make_error(Errc::malformed, run_field);
  return Status::success();
}

// A damaged segment: said once, then every task killed (none can trust what it reads; the handler
// sends no frame any more, so the drives' SyncManager watchdog disables their outputs and the worm
// gears hold the joints: safe hold), and nothing more is read from the segment or recorded.
int stop_on_damaged_segment(Supervisor& supervisor, const TaskProcesses& p, const Error& damage) noexcept {
  (void)std::printf("rescue-motion run: shared segment %s damaged (%s): killing every task; no frame is sent any more, "
                    "the drives' SyncManager watchdog disables their outputs and the worm gears hold the joints "
                    "(safe hold); nothing is recorded from the damaged segment\n",
                    g_run.segment.name().c_str(), damage.what);
  (void)std::fflush(stdout);
  supervisor.stop_restarting();
  for (const std::size_t i : {p.handler, p.manager, p.parser, p.rc_rescue, p.rc_teleop}) supervisor.expect_exit(i);
  if (g_run.tasks.operator_port) supervisor.expect_exit(p.socket);
  supervisor.signal_all(SIGKILL);
  for (const std::size_t i : {p.handler, p.manager, p.parser, p.rc_rescue, p.rc_teleop}) {
    (void)supervisor.wait_exit(i, kTaskStopLimit);
  }
  if (g_run.tasks.operator_port) (void)supervisor.wait_exit(p.socket, kTaskStopLimit);
  (void)std::fprintf(stderr, "rescue-motion run: shared segment damaged (%s); exit status %d\n", damage.what,
                     kExitSegmentDamaged);
  return kExitSegmentDamaged;
}

}  // namespace

int run_task_processes(OperatorSide& side) noexcept {
  RunControl& state = run_control();
  static hal::MonotonicClock supervisor_clock;
  static Supervisor supervisor(supervisor_clock, RestartPolicy{}, stdout);
  // Its lines on the run's time, as the logger's: the run's age now, measured on the run's clock.
  supervisor.set_time_origin(supervisor_clock.now() - (g_run.tasks.clock->now() - g_run.tasks.start));
  const Result<TaskProcesses> started = start_task_processes(supervisor);
  if (!started.ok()) return fail("run", "cannot start the task processes", started.error());
  const TaskProcesses& p = started.value();
  const hal::Nanoseconds start_limit = supervisor_clock.now() + kTaskStartLimit;
  Supervisor::Death death;
  while (state.tasks_started.load(std::memory_order_acquire) < task_count() && !death.critical &&
         supervisor_clock.now() < start_limit) {
    death = supervisor.poll();
    supervisor_clock.sleep_until(supervisor_clock.now() + hal::kNsPerMs);
  }
  declare_init_complete(HeapGuardMode::count);
  while (!death.critical) {
    const Status intact = segment_damage();
    if (!intact.ok()) return stop_on_damaged_segment(supervisor, p, intact.error());
    if (stop_signal() != 0) state.stop.store(true, std::memory_order_release);
    observe_task_cpu(supervisor_clock, state.handler_done.load(std::memory_order_acquire));
    operator_side_pass(side);
    death = supervisor.poll();
    state.health[static_cast<std::size_t>(StatTask::message_parser)].restarts.store(supervisor.restarts(p.parser));
    if (g_run.tasks.operator_port) {
      state.health[static_cast<std::size_t>(StatTask::socket_handler)].restarts.store(supervisor.restarts(p.socket));
    }
    state.health[static_cast<std::size_t>(StatTask::rc_rescue)].restarts.store(supervisor.restarts(p.rc_rescue));
    state.health[static_cast<std::size_t>(StatTask::rc_teleop)].restarts.store(supervisor.restarts(p.rc_teleop));
    if (state.handler_done.load(std::memory_order_acquire)) break;
    supervisor_clock.sleep_until(supervisor_clock.now() + kLoggerPeriod);
  }
  if (death.critical && death.index == p.handler) {
    char how[64];
    Supervisor::describe_wait_status(death.wait_status, how, sizeof how);
    (void)std::printf("rescue-motion run: the EtherCAT handler died (%s): no frame is sent any more; the drives' "
                      "SyncManager watchdog disables their outputs and the worm gears hold the joints (safe hold); "
                      "stopping the other tasks\n", how);
    stop_operator_and_manager(supervisor, p);
    (void)std::fprintf(stderr, "rescue-motion run: the EtherCAT handler died (%s); exit status %d\n", how, kExitTaskDied);
    return kExitTaskDied;
  }
  if (death.critical) {  // the joint manager: the handler disables the drives and ends, then the rest
    state.stop.store(true, std::memory_order_release);
    (void)std::printf("rescue-motion run: the joint manager died: disabling every drive, then stopping\n");
  }
  supervisor.expect_exit(p.handler);
  (void)supervisor.wait_exit(p.handler, kTaskStopLimit + kDisableTimeout);
  operator_side_pass(side);
  disable_enabled_joints();
  stop_operator_and_manager(supervisor, p);
  if (death.critical) {
    (void)std::fprintf(stderr, "rescue-motion run: the joint manager died; exit status %d\n", kExitTaskDied);
    return kExitTaskDied;
  }
  return 0;
}

}  // namespace rescue::app::runner
