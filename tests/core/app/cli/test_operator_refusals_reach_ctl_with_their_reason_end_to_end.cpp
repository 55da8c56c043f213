// Issue 24, every refusal's reason reaches `ctl` (docs/operator.md "Refused commands"), against a real
// `rescue-motion run`: a clear of a joint that is still unreachable names why ("still unreachable:
// repair it first"), a clear of a joint never lost says so; `move` or `hand` for an RC task that does
// not own the motion is refused "not owner (owner: rc0)"; an unknown joint name is named, with the
// list of valid names, before anything is sent.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(OperatorRefusalReasons, ClearOfAnUnreachableJointSaysWhy) {
  OperatorRun run("30", "link-cut");
  ASSERT_TRUE(run.wait_for("reconfiguration step 5")) << run.output();
  const CommandResult clear = run.ctl({"clear", "l_elbow"});
  EXPECT_EQ(clear.status, 1) << clear.out;
  EXPECT_TRUE(has(clear.out, "clear: refused: clear refused: l_elbow: still unreachable: repair it first")) << clear.out;
  const CommandResult never_lost = run.ctl({"--json", "clear", "neck_pan"});
  EXPECT_EQ(never_lost.status, 1) << never_lost.out;
  EXPECT_TRUE(has(never_lost.out, R"("refused":[{"joint":"neck_pan","reason":"clear refused","state":"Enabled","detail":"not recorded lost: nothing to clear"}])"))
      << never_lost.out;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

TEST(OperatorRefusalReasons, InputForATaskThatDoesNotOwnTheMotionIsRefusedNamingTheOwner) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  ASSERT_EQ(run.ctl({"init"}).status, 0);
  ASSERT_EQ(run.ctl({"owner", "0"}).status, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the task takes the word in its next period
  const CommandResult move = run.ctl({"move", "left", "0.4,0.2,0.3,0,0,0", "--task", "1"});
  EXPECT_EQ(move.status, 1) << move.out;
  EXPECT_TRUE(has(move.out, "move: refused: not owner: not owner (owner: rc0)")) << move.out;
  const CommandResult hand = run.ctl({"--json", "hand", "left", "close", "--task", "1"});
  EXPECT_EQ(hand.status, 1) << hand.out;
  EXPECT_EQ(testing::json_field(hand.out, "reason"), "not owner") << hand.out;
  EXPECT_EQ(testing::json_field(hand.out, "detail"), "not owner (owner: rc0)") << hand.out;
  // The owner's own input is taken.
  EXPECT_EQ(run.ctl({"move", "left", "0.4,0.2,0.3,0,0,0", "--task", "0"}).status, 0);
  EXPECT_EQ(run.stop(), 0) << run.output();
}

TEST(OperatorRefusalReasons, AnUnknownJointNameIsNamedWithTheValidNames) {
  const CommandResult bad = testing::run_program({"ctl", "--port", "9", "enable", "l_elbow,tail"});
  EXPECT_EQ(bad.status, 2) << bad.out;
  EXPECT_TRUE(has(bad.out, "'tail' (in 'l_elbow,tail')")) << bad.out;
  EXPECT_TRUE(has(bad.out, "the joints: waist_yaw,neck_pan,neck_tilt,")) << bad.out;
  EXPECT_TRUE(has(bad.out, "l_track,r_track (or all)")) << bad.out;
}

}  // namespace
}  // namespace rescue::app
