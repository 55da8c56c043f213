// Issue 24, all-or-nothing operator commands (docs/operator.md "Refused commands"): a command on several
// joints is checked against every named joint first; if any must refuse, nothing changes and the
// answer names every blocking joint with its reason; otherwise the whole command takes effect.
// Against a real `rescue-motion run` with some joints Enabled, some Ready and one Idle: a refused
// `ctl enable` and `ctl mode` each exit 1 and leave every joint's state in `ctl --json status`
// byte-identical; `--json` names each blocking joint with its reason and state (a joint already where
// the command takes it is not blocking: test_operator_commands_already_done_succeed_and_change_nothing);
// an accepted command on several joints changes all of them.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// Every joint's object of `ctl --json status` up to its position (name, state, mode, reachable, lost).
std::string joint_states(const OperatorRun& run) {
  const CommandResult json = run.ctl({"--json", "status"});
  std::string states;
  for (const JointInfo& joint : kJoints) {
    const std::string object = testing::joint_object(json.out, joint.name);
    states += object.substr(0, object.find(",\"position_rad\"")) + "\n";
  }
  return states;
}

TEST(OperatorAllOrNothing, ARefusedCommandChangesNoJointAndNamesEveryBlockingJoint) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  std::string all_but_waist;  // waist_yaw stays Idle
  for (std::size_t j = 1; j < kJointCount; ++j) all_but_waist += std::string(j == 1 ? "" : ",") + kJoints[j].name;
  ASSERT_EQ(run.ctl({"init", all_but_waist}).status, 0);
  ASSERT_EQ(run.ctl({"disable", "l_hand,r_hand"}).status, 0);             // Ready
  const std::string before = joint_states(run);
  ASSERT_TRUE(has(before, R"({"name":"l_hand","state":"Ready")")) << before;
  ASSERT_TRUE(has(before, R"({"name":"waist_yaw","state":"Idle")")) << before;
  ASSERT_TRUE(has(before, R"({"name":"neck_pan","state":"Enabled")")) << before;

  // enable (all): Idle waist_yaw refuses; l_hand and r_hand could, yet stay Ready (the Enabled ones
  // are already there: not blocking, not named).
  const CommandResult enable = run.ctl({"enable"});
  EXPECT_EQ(enable.status, 1) << enable.out;
  EXPECT_TRUE(has(enable.out, "enable: refused: state machine refusal: waist_yaw: enable in Idle")) << enable.out;
  EXPECT_FALSE(has(enable.out, "neck_pan")) << enable.out;
  EXPECT_FALSE(has(enable.out, "l_hand")) << enable.out;
  EXPECT_EQ(joint_states(run), before);

  // mode csv: the Enabled joints refuse select_mode; the Ready ones stay as they are.
  const CommandResult mode = run.ctl({"mode", all_but_waist, "csv"});
  EXPECT_EQ(mode.status, 1) << mode.out;
  EXPECT_TRUE(has(mode.out, "mode: refused: state machine refusal: neck_pan: select_mode in Enabled")) << mode.out;
  EXPECT_EQ(joint_states(run), before);

  // --json: one object, every blocking joint with its reason and state.
  const CommandResult json = run.ctl({"--json", "enable", "waist_yaw,l_hand,neck_pan"});
  EXPECT_EQ(json.status, 1) << json.out;
  EXPECT_EQ(json.out.rfind(R"({"command":"enable","ok":false,"accepted":false,)", 0), 0U) << json.out;
  EXPECT_TRUE(has(json.out, R"("refused":[{"joint":"waist_yaw","reason":"state machine refusal","state":"Idle","detail":"enable in Idle"}])"))
      << json.out;
  EXPECT_EQ(json.out.find('\n'), json.out.size() - 1) << "one line: " << json.out;
  EXPECT_EQ(joint_states(run), before);

  // Accepted: the whole command takes effect.
  const CommandResult both = run.ctl({"enable", "l_hand,r_hand"});
  EXPECT_EQ(both.status, 0) << both.out;
  const std::string after = joint_states(run);
  EXPECT_TRUE(has(after, R"({"name":"l_hand","state":"Enabled")")) << after;
  EXPECT_TRUE(has(after, R"({"name":"r_hand","state":"Enabled")")) << after;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
