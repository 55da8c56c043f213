// Issue 36 item 9: in `run --threads` the six tasks are threads of one process; `ctl tasks` gives
// each its own thread id (one pid, six distinct tids), each thread carries its task's name (no task
// thread is left as `rescue-motion`), and each task shows its restarts (0) and uptime. Against a
// real `rescue-motion run --threads`.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::first_line;
using testing::OperatorRun;

std::string task_object(const std::string& json, const std::string& name) {
  const std::size_t at = json.find("{\"name\":\"" + name + "\"");
  return at == std::string::npos ? "" : json.substr(at, json.find("\"execution_ns\"", at) - at);
}

constexpr const char* kTasks[] = {"ethercat", "joint-manager", "message-parser", "socket-handler", "rc-rescue", "rc-teleop"};

TEST(TaskThreads, EachTaskThreadHasItsOwnTidAndNameInOneProcess) {
  OperatorRun run("60", nullptr, {"--threads"});
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  testing::CommandResult tasks;
  for (int i = 0; i < 100; ++i) {
    tasks = run.ctl({"--json", "tasks"});
    bool all = tasks.status == 0;
    for (const char* name : kTasks) all = all && !task_object(tasks.out, name).empty();
    if (all) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_EQ(tasks.status, 0) << tasks.out;
  std::set<int> tids;
  for (const char* name : kTasks) {
    const std::string object = task_object(tasks.out, name);
    ASSERT_FALSE(object.empty()) << name << " in " << tasks.out;
    const int pid = std::stoi(testing::json_field(object, "pid"));
    EXPECT_EQ(pid, run.pid()) << name << ": a thread of the run's one process";
    const int tid = std::stoi(testing::json_field(object, "tid"));
    tids.insert(tid);
    EXPECT_EQ(first_line("/proc/" + std::to_string(pid) + "/task/" + std::to_string(tid) + "/comm"), name)
        << "the thread tid names carries its task's name";
    EXPECT_EQ(testing::json_field(object, "restarts"), "0") << name;
    const std::string uptime = testing::json_field(object, "uptime_ms");
    ASSERT_NE(uptime, "null") << name;
    EXPECT_GE(std::stol(uptime), 0) << name;
  }
  EXPECT_EQ(tids.size(), std::size(kTasks)) << "one thread per task: " << tasks.out;
  // The text form shows the same TID column.
  const testing::CommandResult text = run.ctl({"tasks"});
  EXPECT_EQ(text.status, 0) << text.out;
  EXPECT_NE(text.out.find(" TID "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("RESTARTS"), std::string::npos) << text.out;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
