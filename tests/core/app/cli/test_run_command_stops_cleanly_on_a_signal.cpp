// Issue 11 item 5: SIGINT or SIGTERM at any moment of `rescue-motion run`, bring-up included, stops it
// cleanly: exit 0, one line saying where it stopped. Before the fix a signal before OP killed the
// process with no message (exit status 130/143 from the shell, here: terminated by the signal).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <string>
#include <thread>

#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

struct Stopped {
  bool exited{false};
  int status{-1};
  std::string out;
};

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Starts `run --duration 20`, sends `signal` after `delay` (or, with `wait_for`, once the log shows
// it: a loaded host may take longer to reach OP), waits for the end.
Stopped run_and_signal(int signal_number, std::chrono::milliseconds delay, const char* wait_for = nullptr) {
  testing::TempStateDir dir;
  const std::string log = dir.path + "/run.log";
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    (void)dup2(fd, 1);
    (void)dup2(fd, 2);
    execl(kBinary.c_str(), kBinary.c_str(), "run", "--duration", "20", "--state-dir", dir.path.c_str(), nullptr);
    _exit(127);
  }
  Stopped s;
  if (pid < 0) return s;
  std::this_thread::sleep_for(delay);
  for (int i = 0; wait_for != nullptr && i < 1500 && read_all(log).find(wait_for) == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  (void)kill(pid, signal_number);
  int status = 0;
  (void)waitpid(pid, &status, 0);
  s.exited = WIFEXITED(status);
  s.status = s.exited ? WEXITSTATUS(status) : -WTERMSIG(status);
  s.out = read_all(log);
  return s;
}

TEST(RunCommandSignals, SigtermDuringBringUpStopsCleanlyAndSaysWhere) {
  // Sent as soon as bring-up begins: it takes at least 150 ms (the simulated drives' EEPROM reads).
  const Stopped s = run_and_signal(SIGTERM, std::chrono::milliseconds(0), "bringing the EtherCAT network up");
  EXPECT_TRUE(s.exited) << "killed by the signal: " << s.out;
  EXPECT_EQ(s.status, 0) << s.out;
  EXPECT_NE(s.out.find("stopped by signal 15 during bring-up"), std::string::npos) << s.out;
}

TEST(RunCommandSignals, SigintDuringBringUpStopsCleanlyAndSaysWhere) {
  const Stopped s = run_and_signal(SIGINT, std::chrono::milliseconds(0), "bringing the EtherCAT network up");
  EXPECT_TRUE(s.exited) << "killed by the signal: " << s.out;
  EXPECT_EQ(s.status, 0) << s.out;
  EXPECT_NE(s.out.find("stopped by signal 2 during bring-up"), std::string::npos) << s.out;
}

TEST(RunCommandSignals, SigtermInOpStopsCleanlyWithDrivesDisabled) {
  const Stopped s = run_and_signal(SIGTERM, std::chrono::milliseconds(100), "network in OP");
  EXPECT_TRUE(s.exited) << s.out;
  EXPECT_EQ(s.status, 0) << s.out;
  EXPECT_NE(s.out.find("stopped by signal 15 while in OP"), std::string::npos) << s.out;
}

}  // namespace
}  // namespace rescue::app
