// Issue 38, `rescue-motion bench wcet --short` (CI's form; labelled serial, run in the load stage of
// toolchain/check.sh on the release build): on the worst-path scenario every task gets either a pWCET
// (a number, its budget judged) or a refusal naming the failed test (every pWCET n/a), and the exit
// status says which (0 all given and within, 2 refused, 3 over budget); the worst path was driven
// (every slave power-cycled and recovered, the cable into the first slave cut and repaired, frames damaged
// while joints are down with no recovery attempt failed, SDO transfers, the socket handler's budget of operator
// datagrams every period) with no heap after init, and the samples written; the conditions (kernel,
// PREEMPT_RT, CPUs, load) are printed with the figures and a refused task's summary says n/a and why. A run whose first half is typical and second half recovery and services (`--scenario mixed`) is refused by
// the identical-distribution test. It checks the method and the refusal, not the bound. An unknown
// scenario or --scheduling value (rt or normal) is refused with a clear message.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "tests/support/key_value_output.hpp"
#include "tests/support/run_command.hpp"

namespace rescue {
namespace {

using test::value_of;
const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
const char* const kTasks[] = {"ethercat_handler", "joint_manager", "message_parser", "rc_tasks", "socket_handler"};

bool python_has_scipy() { return test::run_command("/usr/bin/python3 -c 'import scipy, matplotlib' 2>/dev/null").exit_status == 0; }

class BenchWcetShort : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!python_has_scipy()) GTEST_SKIP() << "/usr/bin/python3 cannot import scipy and matplotlib (toolchain/setup.sh)";
    ASSERT_NE(::mkdtemp(dir_), nullptr);
  }
  void TearDown() override { (void)std::system(("rm -rf '" + std::string(dir_) + "'").c_str()); }
  char dir_[64] = "/tmp/test-bench-wcet-XXXXXX";
};

TEST_F(BenchWcetShort, EveryTaskGetsAPwcetOrARefusalAndTheExitStatusSaysWhich) {
  const test::CommandOutput run = test::run_command("'" + kProgram + "' bench wcet --short --out " + dir_ + "/out 2>&1");
  const std::string& out = run.out;
  ASSERT_TRUE(run.exit_status == 0 || run.exit_status == 2 || run.exit_status == 3) << out;
  EXPECT_EQ(value_of(out, "heap_allocations_after_init"), "0 allocations") << out;
  EXPECT_EQ(value_of(out, "measured_periods"), "2500 periods per task") << out;
  EXPECT_GE(std::atoi(value_of(out, "power_cycles_of_every_slave").c_str()), 1) << out;
  EXPECT_GE(std::atoi(value_of(out, "cable_cuts_repaired").c_str()), 1) << out;
  EXPECT_GE(std::atoi(value_of(out, "recoveries_to_every_joint_enabled").c_str()), 1) << "the worst path ran to its end: " << out;
  EXPECT_GT(std::atoi(value_of(out, "sdo_transfers").c_str()), 100) << out;
  EXPECT_GE(std::atoi(value_of(out, "damaged_frames").c_str()), 1) << out;
  EXPECT_EQ(value_of(out, "ring_breaks"), "n/a (the tree)") << out;
  EXPECT_NE(value_of(out, "master_recoveries").find(", 0 attempts failed,"), std::string::npos)
      << "the lost mailbox frames asked again: " << out;
  EXPECT_FALSE(value_of(out, "mailbox_repeat_requests").empty()) << out;
  EXPECT_EQ(value_of(out, "socket_handler_max_datagrams_per_wakeup"), "64 (its budget 64)") << out;
  const std::string conditions = value_of(out, "conditions");
  for (const char* part : {"kernel ", "PREEMPT_RT ", " CPUs online", "load average (1 5 15 min) "}) {
    EXPECT_NE(conditions.find(part), std::string::npos) << part << "\n" << out;
  }
  bool any_refused = false;
  bool any_over = false;
  for (const char* task : kTasks) {
    const std::string t(task);
    EXPECT_EQ(value_of(out, t + ".samples"), "2500") << out;
    const std::string verdict = value_of(out, t + ".verdict");
    const std::string pwcet = value_of(out, t + ".pwcet_1e-9_ns");
    if (verdict.rfind("refused: ", 0) == 0) {
      any_refused = true;
      EXPECT_EQ(pwcet, "n/a") << t << ": a refused task has no pWCET\n" << out;
      EXPECT_EQ(value_of(out, t + ".pwcet_1e-12_ci_high_ns"), "n/a") << out;
      EXPECT_EQ(value_of(out, t + ".budget_share_of_period"), "n/a") << out;
      EXPECT_NE(value_of(out, t + ".summary").find("pWCET(1e-9) n/a (refused: "), std::string::npos) << out;
    } else {
      EXPECT_EQ(verdict, "pWCET given (all tests passed)") << out;
      EXPECT_GE(std::atof(pwcet.c_str()), std::atof(value_of(out, t + ".observed_max_ns").c_str()) * 0.5) << out;
    }
    any_over = any_over || value_of(out, t + ".budget") == "over";
    std::ifstream samples(std::string(dir_) + "/out/" + t + ".txt");
    std::string line;
    int values = 0;
    while (std::getline(samples, line)) values += (!line.empty() && line[0] != '#') ? 1 : 0;
    EXPECT_EQ(values, 2500) << t;
  }
  EXPECT_EQ(value_of(out, "message_parser.budget"), "n/a (event driven: no period)") << out;
  EXPECT_EQ(value_of(out, "socket_handler.budget"), "n/a (event driven: no period)") << out;
  EXPECT_EQ(run.exit_status, any_over ? 3 : any_refused ? 2 : 0) << out;
  EXPECT_EQ(::access((std::string(dir_) + "/out/pwcet.png").c_str(), R_OK), 0) << out;
}

TEST_F(BenchWcetShort, ARunThatChangesHalfwayIsRefusedAsNotIdenticallyDistributed) {
  const test::CommandOutput run =
      test::run_command("'" + kProgram + "' bench wcet --short --scenario mixed --no-plot --out " + dir_ + "/out 2>&1");
  EXPECT_NE(run.exit_status, 0) << run.out;
  EXPECT_NE(value_of(run.out, "message_parser.verdict").find("identical distribution: two-sample KS p = "), std::string::npos)
      << "idle, then re-initialising every joint: " << run.out;
  EXPECT_EQ(value_of(run.out, "message_parser.pwcet_1e-9_ns"), "n/a") << run.out;
}

TEST(BenchWcet, AnUnknownScenarioIsRefusedWithTheKnownOnes) {
  const test::CommandOutput run = test::run_command("'" + kProgram + "' bench wcet --scenario calm --out /tmp 2>&1");
  EXPECT_EQ(run.exit_status, 1) << run.out;
  EXPECT_NE(run.out.find("unknown scenario 'calm' (known: typical recovery services worst worst-ring mixed)"), std::string::npos) << run.out;
}

TEST(BenchWcet, AnUnknownSchedulingIsRefused) {
  const test::CommandOutput run = test::run_command("'" + kProgram + "' bench wcet --scheduling fifo --out /tmp 2>&1");
  EXPECT_EQ(run.exit_status, 1) << run.out;
  EXPECT_NE(run.out.find("wcet: --scheduling must be rt or normal"), std::string::npos) << run.out;
}

}  // namespace
}  // namespace rescue
