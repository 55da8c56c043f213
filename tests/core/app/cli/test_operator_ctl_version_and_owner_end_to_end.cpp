// Issue 24, integrator verbs against a running robot (docs/operator.md): `ctl version` names the robot's
// program (git describe of its build), its shared-memory layout version and hash, the build type, and
// the client's own; `ctl owner` with no argument says which RC task owns the motion, whether each task
// is alive and its phase. Both with --json, parsed here.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "core/app/config/build_info.hpp"
#include "core/app/links/task_links.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// The object after "key": in `json` (up to its closing brace).
std::string object_of(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\":{");
  if (at == std::string::npos) return "";
  return json.substr(at + key.size() + 3, json.find('}', at) - at - key.size() - 2);
}

// The object of RC task k in `ctl --json owner`.
std::string task_object(const std::string& json, int k) {
  const std::size_t at = json.find("{\"task\":" + std::to_string(k) + ",");
  return at == std::string::npos ? "" : json.substr(at, json.find('}', at) - at + 1);
}

// `ctl --json owner` once `done` holds for it, or the last answer after 10 s: a task's first heartbeat
// and its taking of the owner word come in its own periods, later on a loaded host.
CommandResult owner_once(OperatorRun& run, bool (*done)(const std::string&)) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  CommandResult answer = run.ctl({"--json", "owner"});
  while (!(answer.status == 0 && done(answer.out)) && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    answer = run.ctl({"--json", "owner"});
  }
  return answer;
}

TEST(OperatorIntegratorVerbs, VersionNamesTheRobotsBuildAndTheClients) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult json = run.ctl({"--json", "version"});
  ASSERT_EQ(json.status, 0) << json.out;
  const std::string robot = object_of(json.out, "robot");
  const std::string client = object_of(json.out, "client");
  EXPECT_EQ(testing::json_field(robot, "program"), build_program_version()) << json.out;
  EXPECT_EQ(testing::json_field(robot, "build_type"), build_type()) << json.out;
  EXPECT_EQ(testing::json_field(robot, "layout_version"), std::to_string(TaskLinks::kLayoutVersion)) << json.out;
  EXPECT_EQ(testing::json_field(robot, "layout_hash").rfind("0x", 0), 0U) << json.out;
  EXPECT_TRUE(has(run.output(), "hash " + testing::json_field(robot, "layout_hash"))) << "the run's own start line";
  EXPECT_EQ(testing::json_field(client, "program"), build_program_version()) << json.out;
  const CommandResult text = run.ctl({"version"});
  EXPECT_EQ(text.status, 0) << text.out;
  EXPECT_TRUE(has(text.out, "robot:  rescue-motion ")) << text.out;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

TEST(OperatorIntegratorVerbs, OwnerWithoutArgumentSaysWhoOwnsTheMotionAndWhoIsAlive) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult nobody = owner_once(run, [](const std::string& out) {
    return testing::json_field(task_object(out, 0), "alive") == "true" &&
           testing::json_field(task_object(out, 1), "alive") == "true";
  });
  ASSERT_EQ(nobody.status, 0) << nobody.out;
  EXPECT_EQ(testing::json_field(nobody.out, "owner"), "null") << nobody.out;
  EXPECT_EQ(testing::json_field(task_object(nobody.out, 0), "alive"), "true") << nobody.out;
  EXPECT_EQ(testing::json_field(task_object(nobody.out, 1), "alive"), "true") << nobody.out;

  ASSERT_EQ(run.ctl({"init"}).status, 0);
  ASSERT_EQ(run.ctl({"owner", "1"}).status, 0);
  const CommandResult owned =
      owner_once(run, [](const std::string& out) { return testing::json_field(out, "owner") == "1"; });
  ASSERT_EQ(owned.status, 0) << owned.out;
  EXPECT_EQ(testing::json_field(owned.out, "owner"), "1") << owned.out;
  EXPECT_EQ(testing::json_field(task_object(owned.out, 1), "owns"), "true") << owned.out;
  EXPECT_EQ(testing::json_field(task_object(owned.out, 0), "owns"), "false") << owned.out;
  EXPECT_NE(testing::json_field(owned.out, "generation"), "0") << owned.out;
  const CommandResult text = run.ctl({"owner"});
  EXPECT_TRUE(has(text.out, "owner: rc1 (teleop)")) << text.out;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
