// `run --check --capture FILE` records every frame of the check (before the fix the option was
// silently dropped and nothing was written); an option that means nothing to --check (a scenario, a
// duration, the operator's ports ...) is refused by name with exit status 1 instead of ignored.
#include <unistd.h>

#include <string>

#include <gtest/gtest.h>

#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

TEST(RunCheckOptions, CaptureRecordsEveryFrameOfTheCheck) {
  const std::string path = ::testing::TempDir() + "check-" + std::to_string(::getpid()) + ".pcapng";
  (void)::unlink(path.c_str());
  const test::CommandOutput check = test::run_command(kBinary + " run --check --capture " + path + " 2>&1");
  ASSERT_EQ(check.exit_status, 0) << check.out;
  const test::CommandOutput decoded = test::run_command(kBinary + " decode " + path + " 2>&1");
  ASSERT_EQ(decoded.exit_status, 0) << decoded.out;
  const auto lines = test::split_lines(decoded.out);
  // Bring-up (SII, SDOs, DC) and 200 ms of cycles: thousands of datagrams, the cyclic LRWs among them.
  EXPECT_GT(lines.size(), 1000U) << decoded.out.substr(0, 2000);
  EXPECT_NE(decoded.out.find("LRW"), std::string::npos);
  (void)::unlink(path.c_str());
}

TEST(RunCheckOptions, OptionsOfARunningRobotAreRefusedByName) {
  for (const std::string option : {"--duration 1", "--scenario link-cut", "--threads", "--control-port 47999", "--initialize"}) {
    const test::CommandOutput check = test::run_command(kBinary + " run --check " + option + " 2>&1");
    EXPECT_EQ(check.exit_status, 1) << option << ": " << check.out;
    const std::string name = option.substr(0, option.find(' '));
    EXPECT_NE(check.out.find("rescue-motion run: " + name + " does not apply to --check (it takes --config, --nic, --ring-nic and --capture)"),
              std::string::npos)
        << option << ": " << check.out;
  }
}

}  // namespace
}  // namespace rescue::app
