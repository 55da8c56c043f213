#include "core/app/runtime/supervisor.hpp"

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cerrno>
#include <cstring>

namespace rescue::app {

Result<std::size_t> Supervisor::add(const SupervisedTask& task) noexcept {
  if (task.body == nullptr) return make_error(Errc::invalid_argument, "supervised task without a body");
  if (count_ == kMaxTasks) return make_error(Errc::capacity_exceeded, "supervised tasks", static_cast<std::uint32_t>(kMaxTasks));
  Slot& slot = tasks_[count_];
  slot.task = task;
  slot.schedule = RestartSchedule(task.criticality, policy_);
  return count_++;
}

Status Supervisor::start(std::size_t index) noexcept {
  Slot& slot = tasks_[index];
  (void)std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t parent = ::getpid();
  const pid_t child = ::fork();
  if (child < 0) return make_error(Errc::io_error, "fork", static_cast<std::uint32_t>(errno));
  if (child == 0) {
    // The task does not outlive the supervisor (and a supervisor that died before this line is seen).
    if (::prctl(PR_SET_PDEATHSIG, slot.task.parent_death_signal) != 0 || ::getppid() != parent) ::_exit(6);
    const int status = slot.task.body(slot.task.context, slot.incarnation);
    (void)std::fflush(nullptr);
    ::_exit(status);
  }
  slot.pid = child;
  slot.exit_expected = false;
  slot.schedule.started(clock_.now());
  return Status::success();
}

void Supervisor::describe_wait_status(int wait_status, char* buffer, std::size_t size) noexcept {
  if (WIFSIGNALED(wait_status)) {
    const int sig = WTERMSIG(wait_status);
    const char* abbreviation = sigabbrev_np(sig);
    (void)std::snprintf(buffer, size, "killed by signal %d (SIG%s)", sig, abbreviation != nullptr ? abbreviation : "?");
  } else if (WIFEXITED(wait_status)) {
    (void)std::snprintf(buffer, size, "exit status %d", WEXITSTATUS(wait_status));
  } else {
    (void)std::snprintf(buffer, size, "wait status 0x%x", static_cast<unsigned>(wait_status));
  }
}

double Supervisor::seconds_now() const noexcept { return hal::seconds(clock_.now() - origin_); }

void Supervisor::reaped(Slot& slot, int wait_status, Death& death, std::size_t index) noexcept {
  const pid_t dead = slot.pid;
  slot.pid = -1;
  if (slot.exit_expected || (slot.task.finished != nullptr && slot.task.finished())) return;
  char how[64];
  describe_wait_status(wait_status, how, sizeof how);
  const hal::Nanoseconds now = clock_.now();
  if (slot.schedule.died(now) == DeathVerdict::stop_run) {
    (void)std::fprintf(log_, "[%8.3f s] supervisor: %s (pid %d) %s: a critical task; stopping the run\n", seconds_now(), slot.task.name,
                       static_cast<int>(dead), how);
    if (!death.critical) death = Death{true, index, wait_status};
    return;
  }
  (void)std::fprintf(log_, "[%8.3f s] supervisor: %s (pid %d) %s; restart %u in %lld ms\n", seconds_now(), slot.task.name, static_cast<int>(dead),
                     how, slot.schedule.restarts(), static_cast<long long>(slot.schedule.last_backoff() / hal::kNsPerMs));
}

Supervisor::Death Supervisor::poll() noexcept {
  Death death;
  for (;;) {
    int wait_status = 0;
    const pid_t ended = ::waitpid(-1, &wait_status, WNOHANG);
    if (ended <= 0) break;
    for (std::size_t i = 0; i < count_; ++i) {
      if (tasks_[i].pid == ended) reaped(tasks_[i], wait_status, death, i);
    }
  }
  const hal::Nanoseconds now = clock_.now();
  for (std::size_t i = 0; i < count_; ++i) {
    Slot& slot = tasks_[i];
    if (!restarting_ || slot.pid > 0 || !slot.schedule.restart_due(now)) continue;
    ++slot.incarnation;
    const Status started = start(i);
    if (!started.ok()) {
      (void)std::fprintf(log_, "[%8.3f s] supervisor: cannot restart %s: %s (errno %u)\n", seconds_now(), slot.task.name, started.error().what,
                         started.error().detail0);
      (void)slot.schedule.died(now);  // try again after the next back-off
      continue;
    }
    (void)std::fprintf(log_, "[%8.3f s] supervisor: %s restarted (pid %d)\n", seconds_now(), slot.task.name, static_cast<int>(slot.pid));
  }
  (void)std::fflush(log_);
  return death;
}

void Supervisor::expect_exit(std::size_t index) noexcept { tasks_[index].exit_expected = true; }

bool Supervisor::wait_exit(std::size_t index, hal::Nanoseconds timeout) noexcept {
  const hal::Nanoseconds deadline = clock_.now() + timeout;
  for (;;) {
    (void)poll();
    if (tasks_[index].pid <= 0) return true;
    if (clock_.now() >= deadline) return false;
    clock_.sleep_until(clock_.now() + hal::kNsPerMs);
  }
}

void Supervisor::signal_all(int signal) noexcept {
  for (std::size_t i = 0; i < count_; ++i) {
    if (tasks_[i].pid > 0) (void)::kill(tasks_[i].pid, signal);
  }
}

}  // namespace rescue::app
