// The tasks' period loops (docs/tasks.md), the same code whether the tasks run as threads of one
// process or as processes: each task applies its row of the task table, records its periods and its
// health, runs its object once per period, and publishes its final figures. A loop reaches the
// shared state only through its ports (TaskLoopPorts, runtime/task_ports.hpp) and its object's; the
// layout check's ports rule fails a call of shared_links() or run_control() here. The entry points take no
// argument: they run on the objects of g_run.tasks (run_context.hpp) with g_run.tasks.ports.
#pragma once


namespace rescue::app::runner {

void run_handler() noexcept;
void run_manager() noexcept;
void run_parser() noexcept;
void run_socket() noexcept;
// The RC tasks on the handler's clock (the heartbeats and reference times its intake compares).
void run_rc_rescue() noexcept;
void run_rc_teleop() noexcept;
// The error-joints storage worker (tasks/error_joints_worker.hpp) at normal priority, in the joint
// manager's process (or the one process with --threads): until the joint manager ended.
void run_storage_worker() noexcept;

}  // namespace rescue::app::runner
