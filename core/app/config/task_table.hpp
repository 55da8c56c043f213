// The firmware's tasks (design brief section 3, paper Table I) as one table: name, scheduling, CPU,
// period, what it shares and what happens when it dies. The runner takes each task's priority and CPU
// from here; `rescue-motion docs tasks` prints it and docs/tasks.md holds that output (a test keeps
// them equal). The numbers live in core/app/config/firmware_config.hpp.
#pragma once

#include <cstdint>
#include <cstdio>

#include "core/base/span.hpp"

namespace rescue::app {

enum class TaskId : std::uint8_t {
  basic_software,
  socket_handler,
  message_parser,
  joint_manager,
  rc_tasks,
  ethercat_handler,
};

struct TaskSpec {
  TaskId id;
  const char* name;
  int priority;            // SCHED_FIFO priority; 0 = SCHED_OTHER (not real-time)
  int cpu;                 // CPU (hardware thread) on the 4-thread motion PC
  std::int64_t period_ns;  // 0 = event driven
  const char* shared_memory;  // what it reads/writes of the shared records
  const char* role;
  const char* built;          // where the code is, or what is not built yet
  // `run` (docs/tasks.md): the process it is, its place in the start-up and shutdown orders (0: not
  // started by the supervisor), and what happens when it dies.
  const char* process;
  int start_order;
  int stop_order;
  const char* on_death;
};

Span<const TaskSpec> task_table() noexcept;
// The CPU a Table I task asks for on this machine: `wanted`, or the machine's last CPU when it has
// fewer (Table I assumes 4 hardware threads; on 2, CPUs 2 and 3 become CPU 1).
int table_cpu_on_this_machine(int wanted) noexcept;
const TaskSpec& task_spec(TaskId id) noexcept;

// A task's priority and CPU set at start-up (the configuration file, config/config_file.hpp), over
// the compiled-in table; before any task starts. docs tasks then prints the table in force.
void set_task_priority(TaskId id, int priority) noexcept;
void set_task_cpu(TaskId id, int cpu) noexcept;
// The SCHED_FIFO priority the runner gives a task: the table's, except that the socket handler and
// the message parser run at normal priority (0) unless a configuration file set theirs.
int runner_priority(TaskId id) noexcept;

// The task table as Markdown tables (docs/tasks.md): scheduling, then processes and their orders.
void write_task_table_markdown(std::FILE* out) noexcept;

}  // namespace rescue::app
