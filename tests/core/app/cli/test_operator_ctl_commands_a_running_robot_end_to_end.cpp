// Issue 12, the operator's path end to end (docs/operator.md): a real `rescue-motion run --listen
// 127.0.0.1 --key FILE` on the in-process simulator, and from separate processes `ctl keygen`, `init`,
// `status` (table and --json), `disable`, `enable`, `hold` (with a disabled joint: named as not
// Enabled): each exits 0 and its output shows the documented effect. A ctl holding another key gets no answer (the robot stays silent to
// unauthenticated peers) and exits 1 saying so; a key file readable by others is refused before
// anything is sent.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>

#include "core/app/links/run_control.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// Lines of `ctl status` for joints in `state` (column STATE).
int joints_in(const std::string& status, const std::string& state) {
  int n = 0;
  for (std::size_t at = status.find('\n'); at != std::string::npos; at = status.find('\n', at + 1)) {
    const std::string line = status.substr(at + 1, status.find('\n', at + 1) - at - 1);
    if (line.size() > 20 && line.compare(20, state.size() + 1, state + " ") == 0) ++n;
  }
  return n;
}

TEST(OperatorCtlEndToEnd, InitStatusDisableEnableHoldAsDocumented) {
  OperatorRun run;
  EXPECT_EQ(run.keygen.status, 0) << run.keygen.out;
  EXPECT_TRUE(has(run.keygen.out, "keygen: wrote a new 32-byte key to " + run.key + " (mode 0600)")) << run.keygen.out;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();

  const CommandResult init = run.ctl({"init"});
  EXPECT_EQ(init.status, 0) << init.out;
  EXPECT_TRUE(has(init.out, "init: accepted")) << init.out;

  const CommandResult status = run.ctl({"status"});
  EXPECT_EQ(status.status, 0) << status.out;
  EXPECT_TRUE(has(status.out, "POS(rad)")) << status.out;
  EXPECT_EQ(joints_in(status.out, "Enabled"), 21) << status.out;
  EXPECT_TRUE(has(status.out, "0  waist_yaw        Enabled    CSP        0.0000")) << status.out;

  const CommandResult json = run.ctl({"--json", "status"});
  EXPECT_EQ(json.status, 0) << json.out;
  EXPECT_EQ(json.out.rfind(R"({"command":"status","ok":true,"cycle":)", 0), 0U) << json.out;
  EXPECT_TRUE(has(json.out, R"({"name":"waist_yaw","state":"Enabled","mode":"CSP","reachable":true,"lost":false,"position_rad":0.000000)"))
      << json.out;

  const CommandResult disable = run.ctl({"disable", "l_hand"});
  EXPECT_EQ(disable.status, 0) << disable.out;
  EXPECT_TRUE(has(disable.out, "disable: accepted")) << disable.out;
  const CommandResult after_disable = run.ctl({"status"});
  EXPECT_EQ(joints_in(after_disable.out, "Enabled"), 20) << after_disable.out;
  EXPECT_EQ(joints_in(after_disable.out, "Ready"), 1) << after_disable.out;
  EXPECT_TRUE(has(after_disable.out, " l_hand           Ready ")) << after_disable.out;
  // hold acts on the Enabled joints and names the others as not Enabled (not as unreachable).
  const CommandResult hold_without_hand = run.ctl({"hold"});
  EXPECT_EQ(hold_without_hand.status, 0) << hold_without_hand.out;
  EXPECT_TRUE(has(hold_without_hand.out, "hold: accepted (not Enabled, left out: l_hand)")) << hold_without_hand.out;

  const CommandResult enable = run.ctl({"enable", "l_hand"});
  EXPECT_EQ(enable.status, 0) << enable.out;
  EXPECT_TRUE(has(enable.out, "enable: accepted")) << enable.out;
  EXPECT_EQ(joints_in(run.ctl({"status"}).out, "Enabled"), 21);

  const CommandResult hold = run.ctl({"hold"});
  EXPECT_EQ(hold.status, 0) << hold.out;
  EXPECT_TRUE(has(hold.out, "hold: accepted")) << hold.out;
  EXPECT_EQ(joints_in(run.ctl({"status"}).out, "Enabled"), 21);

  // A command the state machine refuses: exit 1 and the reason (another mode for an Enabled joint).
  const CommandResult again = run.ctl({"mode", "l_elbow", "csv"});
  EXPECT_EQ(again.status, 1) << again.out;
  EXPECT_TRUE(has(again.out, "mode: refused: state machine refusal: l_elbow: select_mode in Enabled")) << again.out;

  // Issue 21: `ctl tasks` reports what each bounded queue dropped (or deferred), text and --json.
  const CommandResult tasks = run.ctl({"tasks"});
  EXPECT_EQ(tasks.status, 0) << tasks.out;
  const CommandResult tasks_json = run.ctl({"--json", "tasks"});
  EXPECT_EQ(tasks_json.status, 0) << tasks_json.out;
  const std::size_t queues = tasks_json.out.find("\"queues\":{");
  ASSERT_NE(queues, std::string::npos) << tasks_json.out;
  for (const char* name : kDropCounterNames) {
    EXPECT_TRUE(has(tasks.out, std::string(" ") + name + " ")) << name << "\n" << tasks.out;
    EXPECT_NE(testing::json_field(tasks_json.out.substr(queues), name), "") << name << "\n" << tasks_json.out;
  }
  EXPECT_EQ(testing::json_field(tasks_json.out.substr(queues), "outcomes_deferred"), "0") << tasks_json.out;

  EXPECT_EQ(run.stop(), 0) << run.output();
  EXPECT_TRUE(has(run.output(), "rescue-motion run: datagrams ")) << run.output();
}

// `ctl clear JOINTS --moved` reaches the robot's clear (here refused: l_hand was never lost);
// --moved with any other verb is refused before anything is sent.
TEST(OperatorCtlEndToEnd, ClearMovedReachesTheRobotsClear) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult moved = run.ctl({"clear", "l_hand", "--moved"});
  EXPECT_EQ(moved.status, 1) << moved.out;
  EXPECT_TRUE(has(moved.out, "clear: refused: clear refused: l_hand")) << moved.out;
  const CommandResult wrong = run.ctl({"enable", "l_hand", "--moved"});
  EXPECT_NE(wrong.status, 0) << wrong.out;
  EXPECT_TRUE(has(wrong.out, "--moved goes with clear JOINTS")) << wrong.out;
  EXPECT_EQ(run.stop(), 0) << run.output();
  // The clear (its get_epoch and the request); the enable never left ctl.
  EXPECT_TRUE(has(run.output(), "accepted 2,")) << run.output();
}

TEST(OperatorCtlEndToEnd, AnotherKeyGetsNoAnswerAndAnOpenKeyFileIsRefused) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const std::string other = run.dir.path + "/other.key";
  ASSERT_EQ(testing::run_program({"ctl", "keygen", "--key", other}).status, 0);

  const CommandResult wrong = testing::run_program(
      {"ctl", "--key", other, "--port", std::to_string(run.control_port), "--timeout", "0.5", "enable"});
  EXPECT_EQ(wrong.status, 3) << "unreachable: " << wrong.out;
  EXPECT_TRUE(has(wrong.out, "rescue-motion ctl: enable: unreachable: no authentic answer from the robot "
                             "(not running, wrong port, or another key)"))
      << wrong.out;

  ASSERT_EQ(::chmod(other.c_str(), 0644), 0);
  const CommandResult open = testing::run_program({"ctl", "--key", other, "--port", std::to_string(run.control_port), "status"});
  EXPECT_EQ(open.status, 4) << "local: " << open.out;
  EXPECT_TRUE(has(open.out, "is readable by group or others") && has(open.out, "chmod 600 it")) << open.out;

  // The robot counted the wrong key's request and nothing else reached it.
  EXPECT_EQ(run.stop(), 0) << run.output();
  EXPECT_TRUE(has(run.output(), "rescue-motion run: datagrams 1, accepted 0, malformed 0, oversized 0, unauthenticated 1"))
      << run.output();
}

}  // namespace
}  // namespace rescue::app
