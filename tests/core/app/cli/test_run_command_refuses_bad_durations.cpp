// Issue 11 item 7: `--duration` takes a decimal number of seconds above 0: 0 is refused (leaving the
// option out is how to run until a signal), hexadecimal is refused, and an out-of-range value names
// the range. Before the fix: 0 ran forever, 0x10 ran 16 s, and "number out of range" gave no range.
// `bench --help` lists only benchmarks that exist.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

test::CommandOutput run(const std::string& arguments) { return test::run_command(kBinary + " " + arguments + " 2>&1"); }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(RunDuration, ZeroIsRefusedAndSaysHowToRunForever) {
  const test::CommandOutput out = run("run --duration 0");
  EXPECT_EQ(out.exit_status, 1) << out.out;
  EXPECT_TRUE(contains(out.out, "must be above 0 (leave it out to run until SIGINT/SIGTERM)")) << out.out;
}

// Issue 21 item 8: below one period of the EtherCAT handler no cycle would run, and 1e-10 s rounded to
// 0 ns ran until SIGTERM. Refused with the reason and the exit status of any other bad option.
TEST(RunDuration, BelowOnePeriodIsRefusedWithTheReason) {
  for (const char* value : {"0.0000000001", "0.0009"}) {
    const test::CommandOutput out = run(std::string("run --duration ") + value);
    EXPECT_EQ(out.exit_status, 1) << value << "\n" << out.out;
    EXPECT_TRUE(contains(out.out, "must be at least one period of the EtherCAT handler (0.001 s)")) << out.out;
    EXPECT_FALSE(contains(out.out, "bringing the EtherCAT network up")) << out.out;
  }
}

TEST(RunDuration, HexadecimalIsRefused) {
  const test::CommandOutput out = run("run --duration 0x10");
  EXPECT_EQ(out.exit_status, 1) << out.out;
  EXPECT_TRUE(contains(out.out, "not a decimal number")) << out.out;
  EXPECT_FALSE(contains(out.out, "bringing the EtherCAT network up")) << out.out;
}

TEST(RunDuration, OutOfRangeNamesTheRange) {
  const test::CommandOutput out = run("run --duration 1e9");
  EXPECT_EQ(out.exit_status, 1) << out.out;
  EXPECT_TRUE(contains(out.out, "number out of range: allowed 0 to 604800")) << out.out;
}

TEST(BenchHelp, ListsOnlyBenchmarksThatExist) {
  const test::CommandOutput out = run("bench --help");
  EXPECT_FALSE(contains(out.out, "\n  tables ")) << out.out;  // no such benchmark
  EXPECT_TRUE(contains(out.out, "\n  rc ")) << out.out;  // core/app/bench/bench_rc.cpp
  // Every benchmark the help names runs: an unknown one is refused with its reason.
  for (const char* name : {"nic", "core", "codec", "master", "sim", "rc", "latency", "periods", "fig4", "wcet"}) {
    EXPECT_TRUE(contains(out.out, std::string("\n  ") + name + " ")) << name;
  }
}

}  // namespace
}  // namespace rescue::app
