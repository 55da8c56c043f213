// run --check (core/app/runtime/self_check.hpp) against the in-process simulated robot: the network
// reaches OP, no drive reports Operation enabled, every slave goes back to INIT, exit status 0, and
// one line says so.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "core/app/runtime/self_check.hpp"

namespace rescue::app {
namespace {

TEST(RunCheck, ReachesOpAndReturnsToInitOnTheSimulatedRobot) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  SelfCheckOptions options;  // the simulated robot
  SelfCheckReport report;
  EXPECT_EQ(run_self_check(options, out, &report), 0);
  EXPECT_TRUE(report.reached_op);
  EXPECT_TRUE(report.back_in_init);
  EXPECT_FALSE(report.drive_enabled);
  EXPECT_GT(report.slaves, 0U);
  EXPECT_GT(report.cycles_in_op, 0U);
  std::rewind(out);
  char line[512] = {};
  ASSERT_NE(std::fgets(line, sizeof line, out), nullptr);
  EXPECT_NE(std::strstr(line, "rescue-motion run --check: OK: nic sim"), nullptr) << line;
  EXPECT_NE(std::strstr(line, "back in INIT; no drive enabled"), nullptr) << line;
  EXPECT_EQ(std::fgets(line, sizeof line, out), nullptr) << "one line only";
  (void)std::fclose(out);
}

}  // namespace
}  // namespace rescue::app
