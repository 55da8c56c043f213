// `rescue-motion bench rc` runs to the end and reports every figure as a `key: value unit` line
// after the header, with no heap allocation after init; it says that the KDL comparison is the
// separate program, which reports the ratios in its own run. No timing is asserted: the figures are
// for people and docs/kinematics.md.
#include <gtest/gtest.h>

#include <unistd.h>

#include <string>

#include "tests/support/run_command.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
const std::string kKdlProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-bench-rc-kdl";

TEST(BenchRc, PrintsEveryKernelAndThePeriodWithoutHeap) {
  ASSERT_EQ(::access(kProgram.c_str(), X_OK), 0) << kProgram << " is not built";
  const test::CommandOutput out = test::run_command("'" + kProgram + "' bench rc --periods 300 2>&1");
  ASSERT_EQ(out.exit_status, 0) << out.out;
  EXPECT_NE(out.out.find("bench: rc\n"), std::string::npos) << out.out;
  for (const char* kernel : {"rc_fk_arm", "rc_jacobian_arm", "rc_dls_arm", "rc_fk_all", "rc_ik_step", "rc_period"}) {
    for (const char* figure : {"_median: ", "_p99: ", "_max: "}) {
      const std::string key = std::string("\n") + kernel + figure;
      EXPECT_NE(out.out.find(key), std::string::npos) << key << "\n" << out.out;
    }
  }
  EXPECT_NE(out.out.find("\nheap_allocations_after_init: 0 allocations\n"), std::string::npos) << out.out;
  EXPECT_NE(out.out.find("rescue-bench-rc-kdl"), std::string::npos) << out.out;
  EXPECT_EQ(out.out.find("kdl_fk"), std::string::npos) << "the firmware binary has no KDL";
}

TEST(BenchRc, KdlProgramPrintsTheRatiosInTheSameRun) {
  ASSERT_EQ(::access(kKdlProgram.c_str(), X_OK), 0) << kKdlProgram << " is not built";
  const test::CommandOutput out = test::run_command("'" + kKdlProgram + "' --periods 300 2>&1");
  ASSERT_EQ(out.exit_status, 0) << out.out;
  for (const char* key : {"\nrc_fk_arm_median: ", "\nkdl_fk_arm_median: ", "\nkdl_jacobian_arm_p99: ",
                          "\nkdl_wdls_arm_max: ", "\nkdl_fk_ratio_median: ", "\nkdl_jacobian_ratio_median: ",
                          "\nkdl_dls_ratio_median: ", "\nheap_allocations_after_init: 0 allocations\n"}) {
    EXPECT_NE(out.out.find(key), std::string::npos) << key << "\n" << out.out;
  }
}

}  // namespace
}  // namespace rescue
