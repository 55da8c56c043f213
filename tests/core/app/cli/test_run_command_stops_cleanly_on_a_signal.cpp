// Issue 11 item 5: SIGINT or SIGTERM at any moment of `rescue-motion run` stops it cleanly: exit 0,
// one line saying where it stopped (here: in OP; during bring-up: the first-contact test). Before the fix a signal before OP killed the
// process with no message (exit status 130/143 from the shell, here: terminated by the signal).
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
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

// Starts `run --duration 20`, sends `signal` after `delay` (or, with `wait_for`, the moment its
// output shows it: the output comes through a pipe that this thread reads, so it wakes as the line is
// written, not at its next look at a file; bring-up with the SII cache empty lasts only ~120 ms, and a
// loaded host may take longer to reach OP), then reads the rest of the output until the end.
Stopped run_and_signal(int signal_number, std::chrono::milliseconds delay, const char* wait_for = nullptr) {
  testing::TempStateDir dir;
  int out[2] = {-1, -1};
  Stopped s;
  if (pipe(out) != 0) return s;
  const pid_t pid = fork();
  if (pid == 0) {
    (void)dup2(out[1], 1);
    (void)dup2(out[1], 2);
    (void)close(out[0]);
    (void)close(out[1]);
    execl(kBinary.c_str(), kBinary.c_str(), "run", "--duration", "20", "--state-dir", dir.path.c_str(), nullptr);
    _exit(127);
  }
  (void)close(out[1]);
  if (pid < 0) {
    (void)close(out[0]);
    return s;
  }
  std::this_thread::sleep_for(delay);
  char buffer[4096];
  bool signalled = wait_for == nullptr;
  if (signalled) (void)kill(pid, signal_number);
  int status = 0;
  bool ended = false;
  // Until the run has ended and its output is drained (its task processes may hold the pipe open a
  // little longer: what they have written by then is read, they are not waited for).
  for (;;) {
    pollfd readable{out[0], POLLIN, 0};
    const int ready = poll(&readable, 1, ended ? 0 : 20);
    if (ready < 0 && errno == EINTR) continue;
    if (ready > 0) {
      const ssize_t n = read(out[0], buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      s.out.append(buffer, static_cast<std::size_t>(n));
      if (!signalled && s.out.find(wait_for) != std::string::npos) {
        (void)kill(pid, signal_number);
        signalled = true;
      }
      continue;
    }
    if (ended) break;
    ended = waitpid(pid, &status, WNOHANG) == pid;
  }
  (void)close(out[0]);
  if (!ended) {
    if (!signalled) (void)kill(pid, signal_number);  // the line never came: whatever it did, stop it
    (void)waitpid(pid, &status, 0);
  }
  s.exited = WIFEXITED(status);
  s.status = s.exited ? WEXITSTATUS(status) : -WTERMSIG(status);
  return s;
}

// A signal during bring-up: tests/core/app/cli/test_run_command_reports_its_wait_for_first_contact.cpp,
// where the bring-up lasts until it is stopped (no segment answers). Against the simulated robot it
// lasts about 100 ms, less than a loaded host may take to deliver the signal after the line.

TEST(RunCommandSignals, SigtermInOpStopsCleanlyWithDrivesDisabled) {
  const Stopped s = run_and_signal(SIGTERM, std::chrono::milliseconds(100), "network in OP");
  EXPECT_TRUE(s.exited) << s.out;
  EXPECT_EQ(s.status, 0) << s.out;
  EXPECT_NE(s.out.find("stopped by signal 15 while in OP"), std::string::npos) << s.out;
}

}  // namespace
}  // namespace rescue::app
