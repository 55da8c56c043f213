// Issue 35, item 15: `run --scenario cable-damage` (nothing lost) ended with "none marked lost,
// recorded in DIR/error-joints.bin", a file that does not exist. The verdict names the file only when
// a joint was marked lost (and so written); otherwise it says that nothing was recorded.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_directory.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

using ScenarioVerdict = testing::TempDirectoryTest;

TEST_F(ScenarioVerdict, NothingLostNamesNoErrorJointsFile) {
  const test::CommandOutput run =
      test::run_command("timeout -s KILL 120 '" + kProgram + "' run --scenario cable-damage --state-dir '" + dir_ + "' 2>&1");
  ASSERT_EQ(run.exit_status, 0) << run.out;
  EXPECT_NE(run.out.find("rescue-motion run: scenario cable-damage passed: no joint marked lost, nothing recorded\n"), std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("recorded in"), std::string::npos) << run.out;
  struct stat st {};
  EXPECT_NE(::stat(path("error-joints.bin").c_str(), &st), 0) << "nothing lost: no file written";
}

}  // namespace
}  // namespace rescue
