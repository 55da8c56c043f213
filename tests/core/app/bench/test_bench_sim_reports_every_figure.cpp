// `rescue-motion bench sim` runs the simulated robot held and moving to the end and reports every
// figure as a `key: value unit` line after the header (CPU, kernel, privileges), every joint valid
// in every cycle, one frame per cycle, no heap allocation after init. No timing is asserted: the
// figures are for people and docs/simulator.md ("Speed").
#include <gtest/gtest.h>

#include <unistd.h>

#include <regex>
#include <string>

#include "tests/support/run_command.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

TEST(BenchSim, PrintsHeaderAndEveryFigureOfBothRuns) {
  ASSERT_EQ(::access(kProgram.c_str(), X_OK), 0) << kProgram << " is not built";
  const test::CommandOutput out = test::run_command("'" + kProgram + "' bench sim --cycles 300 2>&1");
  ASSERT_EQ(out.exit_status, 0) << out.out;
  for (const char* header : {"bench: sim\n", "\ncpu: ", "\nkernel: ", "\nprivileges: ", "\nrobot_slaves: 23 slaves"}) {
    EXPECT_NE(out.out.find(header), std::string::npos) << header;
  }
  const std::regex figure("^[a-z0-9_]+: [0-9.]+ [a-z%/]+( \\(.*\\))?$");
  std::size_t figures = 0;
  for (const std::string& line : test::split_lines(out.out)) {
    if (std::regex_match(line, figure)) ++figures;
  }
  EXPECT_GE(figures, 20U) << out.out;
  for (const char* run : {"hold", "move"}) {
    const std::string m = std::string("\n") + run;
    for (const char* key : {"_cycles_all_joints_valid: 300 cycles", "_frames_per_cycle: 1.00 frames",
                            "_robot_cycle_host_median: ", "_robot_cycle_host_p99: ", "_segment_cycle_host_median: ",
                            "_segment_cycle_host_p99: ", "_simulated_seconds_per_host_second: ",
                            "_simulated_seconds_per_cpu_second: ", "_host_seconds_per_simulated_hour: ",
                            "_cpu_seconds_per_simulated_hour: "}) {
      EXPECT_NE(out.out.find(m + key), std::string::npos) << run << key << "\n" << out.out;
    }
  }
  EXPECT_NE(out.out.find("\nheap_allocations_after_init: 0 allocations\n"), std::string::npos) << out.out;

  const test::CommandOutput one = test::run_command("'" + kProgram + "' bench sim --cycles 200 --motion move 2>&1");
  ASSERT_EQ(one.exit_status, 0) << one.out;
  EXPECT_EQ(one.out.find("\nhold_"), std::string::npos) << one.out;
  EXPECT_NE(one.out.find("\nmove_cycles_all_joints_valid: 200 cycles"), std::string::npos) << one.out;
  EXPECT_NE(test::run_command("'" + kProgram + "' bench sim --motion sideways 2>&1").exit_status, 0);
}

}  // namespace
}  // namespace rescue
