#include "core/app/runtime/restart_policy.hpp"

namespace rescue::app {

DeathVerdict RestartSchedule::died(hal::Nanoseconds now) noexcept {
  running_ = false;
  if (criticality_ == TaskCriticality::critical) {
    restart_at_ = -1;
    return DeathVerdict::stop_run;
  }
  if (now - started_at_ >= policy_.stable_after) backoff_ = policy_.first_backoff;
  last_backoff_ = backoff_;
  restart_at_ = now + backoff_;
  backoff_ = backoff_ * 2 > policy_.max_backoff ? policy_.max_backoff : backoff_ * 2;
  ++restarts_;
  return DeathVerdict::restart_later;
}

}  // namespace rescue::app
