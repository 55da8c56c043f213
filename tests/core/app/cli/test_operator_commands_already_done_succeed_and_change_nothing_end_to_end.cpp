// Issue 36 item 7, idempotent commands (docs/operator.md "Refused commands"): a command that asks for
// the state a joint is already in succeeds for that joint and changes nothing. Against a real
// `rescue-motion run`: `ctl disable neck_pan; ctl init` initializes neck_pan (it printed 18 refusal
// lines and initialized nothing before); `disable l_hand` twice leaves l_hand Ready (it went on to
// Idle, after which enable was refused); `enable` and `mode` repeated are accepted and name the joints
// they left unchanged.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/json_query.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

class AlreadyThere : public ::testing::Test {
 protected:
  // `joint`'s state and mode in `ctl --json status`, e.g. ["Enabled", "CSP"].
  std::string state_of(const char* joint) const {
    const CommandResult json = run.ctl({"--json", "status"});
    return testing::json_query(run.dir.path, json.out,
                               std::string("[[j['state'], j['mode']] for j in d['joints'] if j['name'] == '") + joint + "'][0]");
  }
  // How many joints `ctl --json status` shows in `state`.
  std::string count_in(const char* state) const {
    const CommandResult json = run.ctl({"--json", "status"});
    return testing::json_query(run.dir.path, json.out, std::string("sum(j['state'] == '") + state + "' for j in d['joints'])");
  }

  OperatorRun run;
};

TEST_F(AlreadyThere, InitAfterOneJointWasDisabledInitializesItAndLeavesTheRest) {
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  ASSERT_EQ(run.ctl({"init"}).status, 0);
  ASSERT_EQ(run.ctl({"disable", "neck_pan"}).status, 0);
  ASSERT_EQ(state_of("neck_pan"), R"(["Ready", "CSP"])");
  const CommandResult init = run.ctl({"init"});
  EXPECT_EQ(init.status, 0) << init.out;
  EXPECT_TRUE(has(init.out, "init: accepted (already initialized, unchanged: 20 joints)")) << init.out;
  EXPECT_EQ(count_in("Enabled"), "21");
  // All already there: accepted at once, nothing sent to the joints.
  const CommandResult again = run.ctl({"--json", "init"});
  EXPECT_EQ(again.status, 0) << again.out;
  EXPECT_EQ(testing::json_query(run.dir.path, again.out, "[d['accepted'], len(d['joints'])]"), "[true, 21]") << again.out;
  EXPECT_EQ(count_in("Enabled"), "21");
  EXPECT_EQ(run.stop(), 0) << run.output();
}

TEST_F(AlreadyThere, DisableEnableAndModeRepeatedChangeNothingTheSecondTime) {
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  ASSERT_EQ(run.ctl({"init"}).status, 0);
  ASSERT_EQ(run.ctl({"disable", "l_hand"}).status, 0);
  ASSERT_EQ(state_of("l_hand"), R"(["Ready", "CSP"])");
  const CommandResult disable = run.ctl({"disable", "l_hand"});
  EXPECT_EQ(disable.status, 0) << disable.out;
  EXPECT_TRUE(has(disable.out, "disable: accepted (already disabled, unchanged: l_hand)")) << disable.out;
  EXPECT_EQ(state_of("l_hand"), R"(["Ready", "CSP"])") << "not stepped back to Idle";
  ASSERT_EQ(run.ctl({"enable", "l_hand"}).status, 0) << "enable still possible";
  const CommandResult enable = run.ctl({"enable", "l_hand"});
  EXPECT_EQ(enable.status, 0) << enable.out;
  EXPECT_TRUE(has(enable.out, "enable: accepted (already Enabled, unchanged: l_hand)")) << enable.out;
  EXPECT_EQ(state_of("l_hand"), R"(["Enabled", "CSP"])");
  // mode: the mode already chosen is no change; another mode of an Enabled joint is still refused.
  ASSERT_EQ(run.ctl({"disable", "l_hand"}).status, 0);
  ASSERT_EQ(run.ctl({"mode", "l_hand", "csv"}).status, 0);
  const CommandResult mode = run.ctl({"mode", "l_hand", "csv"});
  EXPECT_EQ(mode.status, 0) << mode.out;
  EXPECT_TRUE(has(mode.out, "mode: accepted (already in that mode, unchanged: l_hand)")) << mode.out;
  EXPECT_EQ(state_of("l_hand"), R"(["Configured", "CSV"])");
  EXPECT_EQ(run.ctl({"mode", "l_elbow", "csv"}).status, 1) << "l_elbow is Enabled in CSP";
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
