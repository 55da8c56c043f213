// Issue 16, link-quality diagnostics as the operator sees them (docs/operator.md "ctl diag"): a real
// `rescue-motion run --scenario cable-damage` (5 frames damaged on the cable into l_elbow, one second
// after OP) and `ctl diag` / `ctl --json diag` from a separate process: the damaged port's counters
// (l_elbow port 0: 5 invalid frames), the forwarded errors downstream of it, and the warning naming
// the cable between l_shoulder_yaw and l_elbow.
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

TEST(OperatorCtlDiagEndToEnd, ShowsTheDamagedPortsCountersAndTheCable) {
  OperatorRun run("60", "cable-damage");
  ASSERT_EQ(run.keygen.status, 0) << run.keygen.out;
  ASSERT_TRUE(run.wait_for("check the cable between l_shoulder_yaw and l_elbow")) << run.output();

  // The table is published once per round-robin sweep: wait (up to 30 s) until it shows the damage.
  CommandResult diag;
  for (int i = 0; i < 300; ++i) {
    diag = run.ctl({"diag"});
    if (has(diag.out, "19  l_elbow          5/0/0/0")) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(diag.status, 0) << diag.out;
  EXPECT_TRUE(has(diag.out, "per port: invalid frames/RX errors/forwarded RX errors/lost links")) << diag.out;
  EXPECT_TRUE(has(diag.out, "19  l_elbow          5/0/0/0")) << diag.out;         // the damaged port, warned
  EXPECT_TRUE(has(diag.out, "20  l_wrist_yaw      0/0/5/0 ")) << diag.out;        // downstream: forwarded only
  EXPECT_TRUE(has(diag.out, "2   r_shoulder_pitch 0/0/0/0           0/0/0/0")) << diag.out;  // other branches clean
  EXPECT_TRUE(has(diag.out, "receive errors on l_elbow port 0: check the cable between l_shoulder_yaw and l_elbow")) << diag.out;
  EXPECT_FALSE(has(diag.out, "on l_wrist_yaw port")) << diag.out;  // forwarded errors never warn

  const CommandResult json = run.ctl({"--json", "diag"});
  EXPECT_EQ(json.status, 0) << json.out;
  EXPECT_EQ(json.out.rfind(R"({"command":"diag","ok":true,"age_ms":)", 0), 0U) << json.out;
  EXPECT_TRUE(has(json.out, R"("stale":false,"cycle":)")) << json.out;
  EXPECT_TRUE(has(json.out, R"({"position":19,"name":"l_elbow","ports":[{"port":0,"invalid_frames":5,"rx_errors":0,"forwarded_rx_errors":0,"lost_links":0,"warning":")"))
      << json.out;
  EXPECT_TRUE(has(json.out, R"("cable_to":"l_shoulder_yaw"})")) << json.out;

  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
