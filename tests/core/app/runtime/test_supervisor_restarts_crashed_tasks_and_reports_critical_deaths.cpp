// core/app/runtime/supervisor.hpp with real child processes: a restartable task that crashes is
// restarted after its back-off with a log line (its body learns its incarnation); a critical task's
// death is reported to the caller with its wait status and never restarted; an expected exit or a
// task that says it finished is no death.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <string>

#include "core/app/runtime/supervisor.hpp"

namespace rescue::app {
namespace {

int crash_first_then_wait(void* /*context*/, unsigned incarnation) noexcept {
  if (incarnation == 0) (void)::raise(SIGKILL);
  for (;;) ::pause();
}
int exit_7(void* /*context*/, unsigned /*incarnation*/) noexcept { return 7; }
int exit_0(void* /*context*/, unsigned /*incarnation*/) noexcept { return 0; }
bool always_finished() noexcept { return true; }

std::string log_text(std::FILE* log) {
  (void)std::fflush(log);
  std::rewind(log);
  std::string text;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, log) != nullptr) text += buffer;
  return text;
}

RestartPolicy quick() {
  RestartPolicy p;
  p.first_backoff = 20 * hal::kNsPerMs;
  p.max_backoff = 40 * hal::kNsPerMs;
  return p;
}

TEST(Supervisor, CrashedRestartableTaskIsRestartedAfterItsBackoff) {
  hal::MonotonicClock clock;
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  Supervisor supervisor(clock, quick(), log);
  const Result<std::size_t> task = supervisor.add({"crasher", TaskCriticality::restartable, crash_first_then_wait, nullptr});
  ASSERT_TRUE(task.ok());
  ASSERT_TRUE(supervisor.start(task.value()).ok());
  const pid_t first = supervisor.pid(task.value());
  const hal::Nanoseconds until = clock.now() + 5 * hal::kNsPerSec;
  while (supervisor.restarts(task.value()) == 0 && clock.now() < until) {
    EXPECT_FALSE(supervisor.poll().critical);
    clock.sleep_until(clock.now() + hal::kNsPerMs);
  }
  ASSERT_EQ(supervisor.restarts(task.value()), 1U) << log_text(log);
  EXPECT_TRUE(supervisor.running(task.value()));
  EXPECT_NE(supervisor.pid(task.value()), first);
  const std::string text = log_text(log);
  EXPECT_NE(text.find("supervisor: crasher (pid " + std::to_string(first) + ") killed by signal 9 (SIGKILL); restart 1 in 20 ms"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("supervisor: crasher restarted (pid " + std::to_string(supervisor.pid(task.value())) + ")"),
            std::string::npos)
      << text;
  // Every line carries its time ("[   0.021 s] supervisor: ..."), on the supervisor's clock.
  for (std::size_t at = 0; at < text.size(); at = text.find('\n', at) + 1) {
    EXPECT_EQ(text.compare(at, 1, "["), 0) << text.substr(at, 80);
    EXPECT_EQ(text.compare(at + 9, 15, " s] supervisor:"), 0) << text.substr(at, 80);
  }
  // An ordered stop: not a death, not restarted.
  supervisor.expect_exit(task.value());
  supervisor.signal_all(SIGTERM);
  EXPECT_TRUE(supervisor.wait_exit(task.value(), 5 * hal::kNsPerSec));
  EXPECT_EQ(supervisor.restarts(task.value()), 1U);
  EXPECT_EQ(log_text(log).find("restart 2"), std::string::npos);
  (void)std::fclose(log);
}

TEST(Supervisor, CriticalTaskDeathIsReportedWithItsStatusAndNeverRestarted) {
  hal::MonotonicClock clock;
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  Supervisor supervisor(clock, quick(), log);
  const Result<std::size_t> finished = supervisor.add({"done", TaskCriticality::critical, exit_0, nullptr, always_finished});
  const Result<std::size_t> critical = supervisor.add({"vital", TaskCriticality::critical, exit_7, nullptr});
  ASSERT_TRUE(finished.ok() && critical.ok());
  ASSERT_TRUE(supervisor.start(finished.value()).ok());
  ASSERT_TRUE(supervisor.start(critical.value()).ok());
  Supervisor::Death death;
  const hal::Nanoseconds until = clock.now() + 5 * hal::kNsPerSec;
  while ((!death.critical || supervisor.running(finished.value())) && clock.now() < until) {
    const Supervisor::Death d = supervisor.poll();
    if (d.critical) death = d;
    clock.sleep_until(clock.now() + hal::kNsPerMs);
  }
  ASSERT_TRUE(death.critical);
  EXPECT_EQ(death.index, critical.value());
  EXPECT_TRUE(WIFEXITED(death.wait_status) && WEXITSTATUS(death.wait_status) == 7);
  clock.sleep_until(clock.now() + 100 * hal::kNsPerMs);
  EXPECT_FALSE(supervisor.poll().critical);  // reported once
  EXPECT_FALSE(supervisor.running(critical.value()));
  EXPECT_EQ(supervisor.restarts(critical.value()), 0U);
  const std::string text = log_text(log);
  EXPECT_NE(text.find("supervisor: vital (pid"), std::string::npos) << text;
  EXPECT_NE(text.find("exit status 7: a critical task; stopping the run"), std::string::npos) << text;
  EXPECT_EQ(text.find("supervisor: done"), std::string::npos) << "a finished task's exit is no death:\n" << text;
  (void)std::fclose(log);
}

}  // namespace
}  // namespace rescue::app
