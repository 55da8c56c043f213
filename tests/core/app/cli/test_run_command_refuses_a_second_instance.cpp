// Issue 11 item 3: a second `rescue-motion run` on a state directory that a first one is using exits
// non-zero naming the first one's pid, and leaves the first one's error-joints file alone. Before the
// fix both ran and the second wrote "sequence 8: none" over the first's record of a link cut.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(RunCommand, ASecondInstanceOnTheSameStateDirectoryIsRefusedWithTheHoldersPid) {
  testing::TempStateDir dir;
  // The first instance, in the background; its shell prints its pid (exec keeps it).
  const std::string log = dir.path + "/first.log";
  const test::CommandOutput started = test::run_command("sh -c 'exec " + kBinary + " run --duration 4 --state-dir " +
                                                        dir.path + " >" + log + " 2>&1' & echo $!");
  const std::string first_pid = started.out.substr(0, started.out.find('\n'));
  ASSERT_FALSE(first_pid.empty());
  // Wait until it holds the lock (its pid is in the lock file).
  const std::string lock = dir.path + "/rescue-motion.lock";
  for (int i = 0; i < 200 && read_all(lock).find(first_pid) == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_NE(read_all(lock).find(first_pid), std::string::npos);

  const test::CommandOutput second = test::run_command(kBinary + " run --duration 0.2 --state-dir " + dir.path + " 2>&1");
  EXPECT_NE(second.exit_status, 0) << second.out;
  EXPECT_NE(second.out.find("in use by another rescue-motion (pid " + first_pid + ")"), std::string::npos) << second.out;
  EXPECT_EQ(second.out.find("bringing the EtherCAT network up"), std::string::npos) << second.out;
  (void)test::run_command("kill -TERM " + first_pid + "; while kill -0 " + first_pid + " 2>/dev/null; do sleep 0.05; done");
}

}  // namespace
}  // namespace rescue::app
