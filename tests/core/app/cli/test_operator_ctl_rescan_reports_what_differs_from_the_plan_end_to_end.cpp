// Issue 36 item 3, `ctl rescan` against a running robot (docs/operator.md "Rescan"): the master
// identifies the segment again in its cyclic frames and compares it with the plan. Before the
// link-cut scenario cuts l_elbow's cable every device reads as planned (23 devices, no difference);
// after it, l_elbow and the three joints behind it are missing (text and --json), while the other
// joints stay in service: none of them is lost by the rescan. An argument is a usage error (exit 2).
#include <gtest/gtest.h>

#include <string>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::json_field;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(OperatorCtlRescan, NamesTheSlavesACutCableLeftMissing) {
  OperatorRun run("30", "link-cut");
  ASSERT_EQ(run.keygen.status, 0) << run.keygen.out;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult whole = run.ctl({"rescan"});
  ASSERT_EQ(whole.status, 0) << whole.out << run.output();
  if (!has(run.output(), "link lost")) {  // before the cut (1 s after OP): all as planned
    EXPECT_TRUE(has(whole.out, "23 devices on the wire, 23 identified; no difference from the plan\n")) << whole.out;
    EXPECT_TRUE(has(whole.out, "19   RM-JD402")) << whole.out;
  }
  EXPECT_TRUE(has(whole.out, "POS  DEVICE            VENDOR      PRODUCT     REVISION    SERIAL      ALIAS   AS\n")) << whole.out;
  EXPECT_EQ(run.ctl({"rescan", "now"}).status, 2);

  ASSERT_TRUE(run.wait_for("reconfiguration step 5")) << run.output();
  const CommandResult cut = run.ctl({"rescan"});
  ASSERT_EQ(cut.status, 0) << cut.out << run.output();
  EXPECT_TRUE(has(cut.out, "19 devices on the wire, 19 identified; 4 differences from the plan:\n")) << cut.out;
  EXPECT_TRUE(has(cut.out, "  missing: l_elbow (position 19, ")) << cut.out;
  EXPECT_TRUE(has(cut.out, "  missing: l_hand (position 22, ")) << cut.out;
  const CommandResult json = run.ctl({"--json", "rescan"});
  ASSERT_EQ(json.status, 0) << json.out;
  EXPECT_EQ(json_field(json.out, "status"), "ok") << json.out;
  EXPECT_EQ(json_field(json.out, "counted"), "19") << json.out;
  EXPECT_TRUE(has(json.out, R"({"kind":"missing","slave":"l_wrist_yaw","position":null,"text":"missing: l_wrist_yaw)")) << json.out;
  // The rescan took no other slave out: only the four behind the cut are out of service.
  const CommandResult slaves = run.ctl({"slaves"});
  EXPECT_TRUE(has(slaves.out, "l_shoulder_yaw   in exchange")) << slaves.out;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
