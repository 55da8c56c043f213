// What the supervisor does when a task process dies (docs/tasks.md), as pure logic on the clock
// interface so it is tested in virtual time (core/app/runtime/supervisor.hpp does the OS part).
//
//   restartable (socket handler, message parser; later RC tasks): restarted after a back-off that
//     starts at first_backoff and doubles on each death up to max_backoff; a task that ran at least
//     stable_after since its last start is back to first_backoff.
//   critical (EtherCAT handler, joint manager): never restarted; its death stops the run, which exits
//     non-zero with the reason.
#pragma once

#include <cstdint>

#include "hal/time/clock.hpp"

namespace rescue::app {

enum class TaskCriticality : std::uint8_t { critical, restartable };

struct RestartPolicy {
  hal::Nanoseconds first_backoff{100 * hal::kNsPerMs};
  hal::Nanoseconds max_backoff{5 * hal::kNsPerSec};
  hal::Nanoseconds stable_after{10 * hal::kNsPerSec};
};

enum class DeathVerdict : std::uint8_t { restart_later, stop_run };

// One task's restart schedule.
class RestartSchedule {
 public:
  RestartSchedule(TaskCriticality criticality, const RestartPolicy& policy) noexcept
      : criticality_(criticality), policy_(policy), backoff_(policy.first_backoff) {}

  // The task (re)started at `now`.
  void started(hal::Nanoseconds now) noexcept {
    started_at_ = now;
    running_ = true;
    restart_at_ = -1;
  }
  // The task died at `now`: restart_later (restart_at() says when) or stop_run.
  DeathVerdict died(hal::Nanoseconds now) noexcept;
  // Whether a restart is due at `now`.
  bool restart_due(hal::Nanoseconds now) const noexcept { return !running_ && restart_at_ >= 0 && now >= restart_at_; }

  hal::Nanoseconds restart_at() const noexcept { return restart_at_; }
  hal::Nanoseconds last_backoff() const noexcept { return last_backoff_; }
  std::uint32_t restarts() const noexcept { return restarts_; }  // deaths answered with a restart
  bool running() const noexcept { return running_; }

 private:
  TaskCriticality criticality_;
  RestartPolicy policy_;
  hal::Nanoseconds backoff_;
  hal::Nanoseconds last_backoff_{0};
  hal::Nanoseconds started_at_{0};
  hal::Nanoseconds restart_at_{-1};
  std::uint32_t restarts_{0};
  bool running_{false};
};

}  // namespace rescue::app
