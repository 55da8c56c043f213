// Issue 36 item 13: every command's --help (and each `bench NAME --help`) fits a terminal of 100
// columns, the long option texts wrapped under their column.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "core/app/config/command_line.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

void expect_fits(const std::vector<std::string>& args) {
  const testing::CommandResult help = testing::run_program(args);
  EXPECT_EQ(help.status, 0) << help.out;
  EXPECT_EQ(help.out.rfind("usage: rescue-motion ", 0), 0U) << help.out;
  std::istringstream lines(help.out);
  std::size_t count = 0;
  for (std::string line; std::getline(lines, line); ++count) {
    EXPECT_LE(line.size(), kHelpColumns) << args[0] << " --help: " << line;
  }
  EXPECT_GT(count, 3U);
}

TEST(CommandHelp, EveryCommandFits100Columns) {
  for (const char* command : {"run", "sim", "ctl", "decode", "bench", "docs"}) expect_fits({command, "--help"});
}

TEST(CommandHelp, EveryBenchmarkFits100Columns) {
  for (const char* bench : {"nic", "core", "codec", "master", "sim", "rc", "latency", "periods", "fig4", "wcet"}) {
    expect_fits({"bench", bench, "--help"});
  }
}

TEST(CommandHelp, AWrappedOptionContinuesUnderItsDescription) {
  const testing::CommandResult help = testing::run_program({"run", "--help"});
  // --scenario's text is longer than a line: its continuation starts at the description column (31).
  const std::size_t at = help.out.find("\n  --scenario NAME");
  ASSERT_NE(at, std::string::npos) << help.out;
  const std::size_t next = help.out.find('\n', at + 1);
  ASSERT_NE(next, std::string::npos);
  EXPECT_EQ(help.out.substr(next + 1, 31), std::string(31, ' ')) << help.out.substr(at, 300);
  EXPECT_NE(help.out[next + 32], ' ');
}

}  // namespace
}  // namespace rescue::app
