// Issue 24: each task's process and real-time thread carries its task's name (prctl PR_SET_NAME), so
// `ps -eLo comm`, `top -H` and `chrt` tell them apart; `ctl tasks` shows the policy, priority and CPU the
// kernel reports for that thread (the task reads them itself and publishes them), beside the task
// table's wish; a CPU the machine lacks is replaced by its last one and announced
// (docs/configuration.md); each process's main thread (its logger) runs at normal scheduling. Against
// a real `rescue-motion run` (processes mode). Issue 36 item 9: `tid` is the task's thread (its name,
// policy and priority in /proc/PID/task/TID), with restarts and uptime.
#include <gtest/gtest.h>
#include <dirent.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::first_line;
using testing::OperatorRun;

// The threads of `pid` whose comm is `name`: their /proc/PID/task/TID/stat.
std::vector<std::string> threads_named(int pid, const std::string& name) {
  std::vector<std::string> stats;
  const std::string dir = "/proc/" + std::to_string(pid) + "/task";
  DIR* d = ::opendir(dir.c_str());
  if (d == nullptr) return stats;
  while (const dirent* e = ::readdir(d)) {
    if (e->d_name[0] == '.') continue;
    if (first_line(dir + "/" + e->d_name + "/comm") == name) stats.push_back(first_line(dir + "/" + e->d_name + "/stat"));
  }
  (void)::closedir(d);
  return stats;
}

// Field n (1-based, as proc(5) numbers them) of a stat line, after the "(comm)".
long stat_field(const std::string& stat, int n) {
  std::istringstream rest(stat.substr(stat.rfind(')') + 2));
  std::string field;
  for (int i = 3; i <= n; ++i) rest >> field;
  return std::stol(field);
}

// The object of task `name` in `ctl --json tasks`.
std::string task_object(const std::string& json, const std::string& name) {
  const std::size_t at = json.find("{\"name\":\"" + name + "\"");
  return at == std::string::npos ? "" : json.substr(at, json.find("\"execution_ns\"", at) - at);
}

TEST(TaskNamesAndSchedule, EveryTaskProcessAndThreadIsNamedAndCtlTasksShowsTheKernelsView) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  // Each task publishes its figures once it is past its set-up: ask until all six have.
  testing::CommandResult tasks;
  for (int i = 0; i < 100; ++i) {
    tasks = run.ctl({"--json", "tasks"});
    if (tasks.status == 0 && task_object(tasks.out, "joint-manager") != "" && task_object(tasks.out, "rc-teleop") != "" &&
        task_object(tasks.out, "message-parser") != "" && task_object(tasks.out, "socket-handler") != "" &&
        task_object(tasks.out, "rc-rescue") != "" && task_object(tasks.out, "ethercat") != "") {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_EQ(tasks.status, 0) << tasks.out;
  for (const char* name : {"ethercat", "joint-manager", "message-parser", "socket-handler", "rc-rescue", "rc-teleop"}) {
    const std::string object = task_object(tasks.out, name);
    ASSERT_FALSE(object.empty()) << name << " in " << tasks.out;
    const int pid = std::stoi(testing::json_field(object, "pid"));
    EXPECT_EQ(first_line("/proc/" + std::to_string(pid) + "/comm"), name) << "the process carries its task's name";
    const std::vector<std::string> threads = threads_named(pid, name);
    ASSERT_GE(threads.size(), 2U) << name << ": the process and its task thread";
    // The task thread is the one `tid` names (issue 36 item 9: what `chrt -p TID` shows), not the
    // process's main thread (its logger): its name, policy and priority are the ones reported.
    const std::string policy = testing::json_field(object, "policy");
    const long want_policy = policy == "FIFO" ? 1 : policy == "RR" ? 2 : policy == "OTHER" ? 0 : -1;
    const int tid = std::stoi(testing::json_field(object, "tid"));
    EXPECT_NE(tid, pid) << name << ": the task's thread, not its process";
    const std::string task_dir = "/proc/" + std::to_string(pid) + "/task/" + std::to_string(tid);
    EXPECT_EQ(first_line(task_dir + "/comm"), name) << "the thread tid names is the task's";
    const std::string stat = first_line(task_dir + "/stat");
    ASSERT_FALSE(stat.empty()) << name << ": tid " << tid << " is a thread of pid " << pid;
    // proc(5): 40 rt_priority, 41 policy.
    EXPECT_EQ(stat_field(stat, 41), want_policy) << name << ": " << object;
    EXPECT_EQ(stat_field(stat, 40), std::stol(testing::json_field(object, "priority"))) << name << ": " << object;
    EXPECT_EQ(testing::json_field(object, "restarts"), "0") << name;
    EXPECT_NE(testing::json_field(object, "uptime_ms"), "null") << name << ": started, so its uptime is known";
    // The process's main thread, its logger, runs at normal scheduling: the handler's process is
    // forked at the handler's priority and CPU (its task thread starts at them at once) and gives
    // them back for its logger.
    EXPECT_EQ(stat_field(first_line("/proc/" + std::to_string(pid) + "/stat"), 41), 0) << name << ": its logger thread";
    const long cpus = ::sysconf(_SC_NPROCESSORS_ONLN);
    const int table_cpu = std::stoi(testing::json_field(object, "table_cpu"));
    EXPECT_LT(table_cpu, cpus) << name << ": the CPU asked for exists on this machine";
    if (policy == "FIFO") {
      EXPECT_EQ(testing::json_field(object, "cpu"), std::to_string(table_cpu)) << name << " pinned";
    }
  }
  // The table asks for CPUs 2 and 3: on a machine with fewer, each substitution is announced.
  if (::sysconf(_SC_NPROCESSORS_ONLN) < 4) {
    EXPECT_NE(run.output().find("ethercat: CPU 3 is not on this machine"), std::string::npos) << run.output();
  }
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
