// Issue 24, `rescue-motion bench`: `bench fig4 --periods 500` run from an empty directory (no source
// tree around it) finds its plot script beside the program and writes its PNG, which states its
// conditions (issue 36 item 12: kernel, PREEMPT_RT, CPUs, affinity, load, in its Description chunk); a plot script that is
// not there is named with where it was looked for, before any measuring; `bench NAME --help` describes
// NAME's own options; an unknown name, and an option the benchmark does not take, are refused.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/support/run_command.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(BenchFig4Plot, FromAnEmptyDirectoryItWritesItsPng) {
  if (test::run_command("/usr/bin/python3 -c 'import matplotlib' 2>/dev/null").exit_status != 0) {
    GTEST_SKIP() << "/usr/bin/python3 cannot import matplotlib (python3-matplotlib, toolchain/setup.sh)";
  }
  char dir[] = "/tmp/test-bench-fig4-plot-XXXXXX";
  ASSERT_NE(::mkdtemp(dir), nullptr);
  const test::CommandOutput out =
      test::run_command(std::string("cd '") + dir + "' && '" + kProgram + "' bench fig4 --periods 500 --out " + dir + "/out 2>&1");
  EXPECT_EQ(out.exit_status, 0) << out.out;
  struct stat st {};
  ASSERT_EQ(::stat((std::string(dir) + "/out/fig4.png").c_str(), &st), 0) << out.out;
  EXPECT_GT(st.st_size, 1000) << "a PNG, not an empty file";
  std::ifstream png(std::string(dir) + "/out/fig4.png", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(png)), std::istreambuf_iterator<char>());
  for (const char* condition : {"Description", "kernel ", "PREEMPT_RT ", "CPUs online", "Table I affinity ", "load: stress,udp"}) {
    EXPECT_TRUE(has(bytes, condition)) << "the PNG's text chunk names " << condition;
  }
  EXPECT_EQ(std::system(("rm -rf '" + std::string(dir) + "'").c_str()), 0);
}

TEST(BenchFig4Plot, AMissingPlotScriptIsNamedBeforeMeasuring) {
  const test::CommandOutput out =
      test::run_command("'" + kProgram + "' bench fig4 --periods 10 --plot-script /nonexistent/plot.py --out /tmp 2>&1");
  EXPECT_EQ(out.exit_status, 1) << out.out;
  EXPECT_TRUE(has(out.out, "no plot script (looked: /nonexistent/plot.py (--plot-script))")) << out.out;
  EXPECT_FALSE(has(out.out, "periods_per_case")) << "refused before measuring: " << out.out;
}

TEST(BenchHelp, EachBenchmarkDescribesItsOwnOptionsAndRefusesOthers) {
  const test::CommandOutput fig4 = test::run_command("'" + kProgram + "' bench fig4 --help 2>&1");
  EXPECT_EQ(fig4.exit_status, 0) << fig4.out;
  EXPECT_TRUE(has(fig4.out, "usage: rescue-motion bench fig4")) << fig4.out;
  EXPECT_TRUE(has(fig4.out, "--plot-script PATH")) << fig4.out;
  EXPECT_FALSE(has(fig4.out, "--frames")) << fig4.out;
  const test::CommandOutput codec = test::run_command("'" + kProgram + "' bench codec --help 2>&1");
  EXPECT_TRUE(has(codec.out, "--frames N")) << codec.out;
  EXPECT_FALSE(has(codec.out, "--load")) << codec.out;
  EXPECT_NE(fig4.out, codec.out);

  const test::CommandOutput bogus = test::run_command("'" + kProgram + "' bench bogus --help 2>&1");
  EXPECT_NE(bogus.exit_status, 0) << bogus.out;
  EXPECT_TRUE(has(bogus.out, "unknown benchmark 'bogus'")) << bogus.out;
  const test::CommandOutput wrong = test::run_command("'" + kProgram + "' bench core --frames 3 2>&1");
  EXPECT_NE(wrong.exit_status, 0) << wrong.out;
  EXPECT_TRUE(has(wrong.out, "--frames does not apply to core")) << wrong.out;
}

}  // namespace
}  // namespace rescue
