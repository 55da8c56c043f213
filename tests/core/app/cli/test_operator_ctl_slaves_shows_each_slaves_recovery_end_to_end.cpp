// Issue 22, `ctl slaves` shows each slave's online recovery (docs/operator.md): a real
// `rescue-motion run --scenario power-cycle` (l_elbow's drive power-cycled one second after OP) and
// `ctl slaves` / `ctl --json slaves` from a separate process once the master recovered it: l_elbow in
// OP with its recovery state Idle and the time since that state changed (its joint stays out of service
// until an operator clears it); the slaves that never left the exchange say their state never changed.
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

TEST(OperatorCtlSlavesEndToEnd, ShowsTheRecoveryStateAndHowLongAgoItChanged) {
  OperatorRun run("60", "power-cycle");
  ASSERT_EQ(run.keygen.status, 0) << run.keygen.out;
  ASSERT_TRUE(run.wait_for("link recovered: l_elbow")) << run.output();

  const CommandResult text = run.ctl({"slaves"});
  EXPECT_EQ(text.status, 0) << text.out;
  EXPECT_TRUE(has(text.out, "RECOVERY     CHANGED")) << text.out;
  EXPECT_TRUE(has(text.out, "19  0x1013  OP     l_elbow          out of service   Idle         ")) << text.out;
  EXPECT_TRUE(has(text.out, " s ago\n")) << text.out;
  EXPECT_TRUE(has(text.out, "8   0x1008  OP     r_hand           in exchange      Idle         never\n")) << text.out;

  const CommandResult json = run.ctl({"--json", "slaves"});
  EXPECT_EQ(json.status, 0) << json.out;
  const std::string elbow = R"("name":"l_elbow","service":"out of service","recovery":"Idle","recovery_changed_ms_ago":)";
  const std::size_t at = json.out.find(elbow);
  ASSERT_NE(at, std::string::npos) << json.out;
  const char after = json.out[at + elbow.size()];
  EXPECT_TRUE(after >= '0' && after <= '9') << json.out;  // a number of ms: it changed (Op -> Idle)
  EXPECT_TRUE(has(json.out, R"("name":"r_hand","service":"in exchange","recovery":"Idle","recovery_changed_ms_ago":null})"))
      << json.out;

  // Stopped before the scenario's own end: its verdict (the exit status) is not this test's subject.
  (void)run.stop();
}

}  // namespace
}  // namespace rescue::app
