// The supervisor of `run`'s task processes (docs/tasks.md): the parent process, which owns the
// shared-memory segment, forks each task as a process of the one binary (the child runs the task's
// body, then _exit with its return value: it never runs the parent's static destructors, so it never
// unlinks the segment), reaps them, restarts a restartable one that died after its back-off
// (restart_policy.hpp) with a log line, and reports a critical one's death to the caller.
//
// Single-threaded: call poll() from the supervisor's loop. Nothing here allocates.
#pragma once

#include <sys/types.h>

#include <array>
#include <csignal>
#include <cstddef>
#include <cstdio>

#include "core/app/runtime/restart_policy.hpp"
#include "core/base/result.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

// Runs in the child; returns its exit status. `incarnation` is 0 for the first start, then 1, 2...
using TaskBody = int (*)(void* context, unsigned incarnation) noexcept;

struct SupervisedTask {
  const char* name{""};
  TaskCriticality criticality{TaskCriticality::critical};
  TaskBody body{nullptr};
  void* context{nullptr};
  // Optional: true once the task's end is ordered (it finished its work); its exit is then no death.
  bool (*finished)() noexcept {nullptr};
  // Sent to the task by the kernel when the supervisor dies (PR_SET_PDEATHSIG), even by SIGKILL.
  int parent_death_signal{SIGKILL};
};

class Supervisor {
 public:
  static constexpr std::size_t kMaxTasks = 8;

  Supervisor(hal::Clock& clock, const RestartPolicy& policy, std::FILE* log) noexcept
      : clock_(clock), policy_(policy), log_(log), origin_(clock.now()) {}

  // Every log line starts "[SECONDS s]" since `origin` on this supervisor's clock (default: its
  // construction), so its lines read on the same time as the run's other lines.
  void set_time_origin(hal::Nanoseconds origin) noexcept { origin_ = origin; }
  // Seconds since the origin now: the stamp of a line about these tasks printed elsewhere.
  double seconds_now() const noexcept;

  // Adds a task (not started). Errors: capacity_exceeded, invalid_argument (no body).
  Result<std::size_t> add(const SupervisedTask& task) noexcept;
  // Forks task `index`. Errors: io_error "fork" (errno in detail0).
  Status start(std::size_t index) noexcept;

  struct Death {
    bool critical{false};
    std::size_t index{0};
    int wait_status{0};
  };
  // Reaps every child that ended (logging unexpected deaths), restarts those due. Returns the first
  // critical task that died unexpectedly since the last call, if any (critical == true).
  Death poll() noexcept;

  // The task's next exit is ordered (a clean stop): not logged as a death, not restarted.
  void expect_exit(std::size_t index) noexcept;
  // Polls until task `index` has exited or `timeout` passed; true when it exited.
  bool wait_exit(std::size_t index, hal::Nanoseconds timeout) noexcept;
  bool running(std::size_t index) const noexcept { return tasks_[index].pid > 0; }
  const char* name(std::size_t index) const noexcept { return tasks_[index].task.name; }
  // From now on no task is restarted (the run is stopping).
  void stop_restarting() noexcept { restarting_ = false; }
  pid_t pid(std::size_t index) const noexcept { return tasks_[index].pid; }
  unsigned restarts(std::size_t index) const noexcept { return tasks_[index].incarnation; }
  // Sends `signal` to every running child.
  void signal_all(int signal) noexcept;

  // "exit status N" / "killed by signal N (NAME)" into `buffer`.
  static void describe_wait_status(int wait_status, char* buffer, std::size_t size) noexcept;

 private:
  struct Slot {
    SupervisedTask task{};
    RestartSchedule schedule{TaskCriticality::critical, RestartPolicy{}};
    pid_t pid{-1};
    unsigned incarnation{0};
    bool exit_expected{false};
  };
  void reaped(Slot& slot, int wait_status, Death& death, std::size_t index) noexcept;

  hal::Clock& clock_;
  RestartPolicy policy_;
  std::FILE* log_;
  hal::Nanoseconds origin_;
  std::array<Slot, kMaxTasks> tasks_{};
  std::size_t count_{0};
  bool restarting_{true};
};

}  // namespace rescue::app
