// --threads: the tasks as threads of this process, the logger in the main thread (task_modes.hpp).
#include "core/app/runtime/task_modes.hpp"

#include <cstdio>
#include <thread>

#include "core/app/config/command_line.hpp"
#include "core/app/runtime/run_context.hpp"
#include "core/app/runtime/run_log.hpp"
#include "core/app/runtime/task_cpu.hpp"
#include "core/app/runtime/task_loops.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/memory/heap_guard.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app::runner {

int run_task_threads(OperatorSide& side) noexcept {
  (void)std::fflush(stdout);
  RunControl& state = run_control();
  g_run.storage_stop.store(false, std::memory_order_relaxed);
  std::thread storage_thread(run_storage_worker);  // normal priority: created by this (normal) thread
  std::thread manager_thread(run_manager);
  std::thread handler_thread(run_handler);
  std::thread parser_thread(run_parser);
  std::thread socket_thread;
  if (g_run.tasks.operator_port) socket_thread = std::thread(run_socket);
  // The two RC tasks compute every period; only the Motion owner's references reach the joints.
  std::thread rescue_thread(run_rc_rescue);
  std::thread teleop_thread(run_rc_teleop);
  // Init is complete once every task is past its set-up (thread start-up allocates).
  hal::MonotonicClock logger_clock;
  while (state.tasks_started.load(std::memory_order_acquire) < task_count()) {
    logger_clock.sleep_until(logger_clock.now() + hal::kNsPerMs);
  }
  declare_init_complete(HeapGuardMode::count);
  for (;;) {
    const bool done = state.handler_done.load(std::memory_order_acquire);
    observe_task_cpu(logger_clock, done);
    handler_side_pass();
    manager_side_pass();
    operator_side_pass(side);
    if (done) break;
    logger_clock.sleep_until(logger_clock.now() + kLoggerPeriod);
  }
  handler_thread.join();
  report_if_never_in_op();
  disable_enabled_joints();
  state.operator_stop.store(true, std::memory_order_release);
  parser_thread.join();
  if (socket_thread.joinable()) socket_thread.join();
  state.rc_stop.store(true, std::memory_order_release);
  rescue_thread.join();
  teleop_thread.join();
  state.manager_stop.store(true, std::memory_order_release);
  manager_thread.join();
  storage_thread.join();  // ends once the joint manager ended (storage_stop)
  handler_side_pass();
  manager_side_pass();
  if (g_run.tasks.options->capture_path != nullptr) {
    const Status closed = finish_capture(g_run.tasks.options->capture_path);
    if (!closed.ok()) return fail("run", "cannot close the capture file", closed.error());
  }
  return 0;
}

}  // namespace rescue::app::runner
