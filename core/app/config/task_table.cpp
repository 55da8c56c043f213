#include "core/app/config/task_table.hpp"

#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <iterator>

#include "core/app/config/firmware_config.hpp"

namespace rescue::app {
namespace {

// clang-format off
// Not const: a configuration file may move a task (set_task_priority, set_task_cpu), before the tasks start.
TaskSpec kTasks[] = {  // NOLINT(cppcoreguidelines-avoid-non-const-global-variables)
  {TaskId::basic_software, "basic software", config::kBasicSoftwarePriority, config::kBasicSoftwareCpu, config::kLoggerPeriodNs,
   "no", "the operating system; the firmware's logger (events, capture file)", "runtime/run_log.cpp (logger)",
   "the supervisor (the parent: owns the segment, starts, restarts and stops the others)", 0, 0,
   "the run ends; even on SIGKILL the EtherCAT handler gets SIGTERM (disables every drive, then ends) and the others SIGKILL (PR_SET_PDEATHSIG); the next run replaces the stale segment"},
  {TaskId::socket_handler, "socket handler", config::kSocketHandlerPriority, config::kSocketHandlerCpu, 0,
   "partly (sensor data)", "UDP from the operator and the other two computers; every datagram validated", "tasks/socket_handler.cpp",
   "its own (with a key file)", 4, 2, "restarted after a back-off (100 ms doubling to 5 s), logged; a new replay epoch (datagrams of the old one are refused)"},
  {TaskId::message_parser, "message parser", config::kMessageParserPriority, config::kMessageParserCpu, 0,
   "no (queues)", "operator messages to the joint handle queue and the RC tasks' inputs", "tasks/message_parser.cpp",
   "its own", 3, 2, "restarted after a back-off (100 ms doubling to 5 s), logged"},
  {TaskId::joint_manager, "joint manager", config::kJointManagerPriority, config::kJointManagerCpu, config::kJointManagerPeriodNs,
   "yes", "joint status DFA, limit monitoring, reconfiguration, error-joints file, drive demand", "tasks/joint_manager.cpp",
   "its own", 2, 4, "critical: the handler disables every drive, the others stop, exit status 4 with the reason"},
  {TaskId::rc_tasks, "RC tasks", config::kRcTaskPriority, config::kRcTaskCpu, config::kRcTaskPeriodNs,
   "yes (own reference space)", "kinematics: next joint references every period (rescue, teleop); the Motion owner's drive the joints", "tasks/rescue_task.cpp, tasks/teleop_task.cpp, links/reference_space.hpp, tasks/motion_intake.cpp",
   "one each (rc-rescue, rc-teleop)", 5, 3,
   "restarted after a back-off (100 ms doubling to 5 s), logged, from its initial state; if it owned the motion, the handler's intake releases the owner word once its heartbeat is kOwnerDeadAfterPeriods old (every joint holds), and an operator's take re-takes it"},
  {TaskId::ethercat_handler, "EtherCAT handler", config::kEthercatHandlerPriority, config::kEthercatHandlerCpu, config::kEthercatHandlerPeriodNs,
   "yes", "one frame with every slave per period; joint state, references, limits, safe stop", "tasks/ethercat_handler.cpp",
   "its own (with the NIC, the simulated robot and the capture file)", 1, 1,
   "critical: no frame any more, the drives' SyncManager watchdog disables their outputs, worm gears hold (safe hold); the others stop; exit status 4 with the reason"},
};
// clang-format on
bool g_operator_priority_set[std::size(kTasks)] = {};  // NOLINT(cppcoreguidelines-avoid-non-const-global-variables)

TaskSpec* find_task(TaskId id) noexcept {
  TaskSpec* found = std::find_if(std::begin(kTasks), std::end(kTasks), [id](const TaskSpec& t) { return t.id == id; });
  return found != std::end(kTasks) ? found : nullptr;
}

}  // namespace

Span<const TaskSpec> task_table() noexcept { return {kTasks}; }

int table_cpu_on_this_machine(int wanted) noexcept {
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  if (online <= 0 || wanted < online) return wanted;
  return static_cast<int>(online - 1);
}

const TaskSpec& task_spec(TaskId id) noexcept {
  const TaskSpec* found = find_task(id);
  return found != nullptr ? *found : kTasks[0];  // unreachable: every TaskId has a row (test_task_table_covers_every_task)
}

void set_task_priority(TaskId id, int priority) noexcept {
  TaskSpec* task = find_task(id);
  if (task == nullptr) return;
  g_operator_priority_set[static_cast<std::size_t>(task - std::begin(kTasks))] = true;
  task->priority = priority;
}

void set_task_cpu(TaskId id, int cpu) noexcept {
  TaskSpec* task = find_task(id);
  if (task != nullptr) task->cpu = cpu;
}

int runner_priority(TaskId id) noexcept {
  const TaskSpec* task = find_task(id);
  if (task == nullptr) return 0;
  const bool operator_task = id == TaskId::socket_handler || id == TaskId::message_parser;
  if (operator_task && !g_operator_priority_set[static_cast<std::size_t>(task - std::begin(kTasks))]) return 0;
  return task->priority;
}

void write_task_table_markdown(std::FILE* out) noexcept {
  (void)std::fprintf(out, "| task | scheduling | CPU | period | shared memory | role | code (core/app/) |\n");
  (void)std::fprintf(out, "|---|---|---|---|---|---|---|\n");
  for (const TaskSpec& t : kTasks) {
    // What the runner applies (runner_priority), not Table I's wish: the socket handler and the
    // message parser run SCHED_OTHER unless a configuration file sets their priority.
    char sched[48];
    const int applied = runner_priority(t.id);
    if (applied > 0) {
      (void)std::snprintf(sched, sizeof sched, "SCHED_FIFO %d", applied);
    } else if (t.priority > 0) {
      (void)std::snprintf(sched, sizeof sched, "SCHED_OTHER (Table I: FIFO %d)", t.priority);
    } else {
      (void)std::snprintf(sched, sizeof sched, "SCHED_OTHER");
    }
    char period[32];
    if (t.period_ns > 0) {
      (void)std::snprintf(period, sizeof period, "%" PRId64 " us", t.period_ns / 1000);
    } else {
      (void)std::snprintf(period, sizeof period, "on input");
    }
    (void)std::fprintf(out, "| %s | %s | %d | %s | %s | %s | %s |\n", t.name, sched, t.cpu, period, t.shared_memory, t.role,
                       t.built);
  }
  (void)std::fprintf(out, "\n| task | process in `run` | start | stop | when it dies |\n|---|---|---|---|---|\n");
  for (const TaskSpec& t : kTasks) {
    char start[16] = "-";
    char stop[16] = "-";
    if (t.start_order > 0) (void)std::snprintf(start, sizeof start, "%d", t.start_order);
    if (t.stop_order > 0) (void)std::snprintf(stop, sizeof stop, "%d", t.stop_order);
    (void)std::fprintf(out, "| %s | %s | %s | %s | %s |\n", t.name, t.process, start, stop, t.on_death);
  }
}

}  // namespace rescue::app
