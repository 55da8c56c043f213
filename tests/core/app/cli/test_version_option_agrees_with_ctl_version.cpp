// Issue 36 item 13: `rescue-motion --version` prints what `ctl version` calls this program (its client
// line: git describe of the build and the build type), and `rescue-motion --help` names the option.
#include <gtest/gtest.h>

#include <string>

#include "core/app/config/build_info.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

TEST(VersionOption, PrintsTheBuildAsCtlVersionDoes) {
  const testing::CommandResult version = testing::run_program({"--version"});
  EXPECT_EQ(version.status, 0);
  EXPECT_EQ(version.out, std::string("rescue-motion ") + build_program_version() + " (" + build_type() + " build)\n");
  const testing::CommandResult help = testing::run_program({"--help"});
  EXPECT_NE(help.out.find("'rescue-motion --version'"), std::string::npos) << help.out;
}

}  // namespace
}  // namespace rescue::app
