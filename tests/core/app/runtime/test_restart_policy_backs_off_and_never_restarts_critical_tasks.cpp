// core/app/runtime/restart_policy.hpp in virtual time: a restartable task comes back after a
// back-off that doubles up to its cap and resets once the task ran stably; a critical task's death
// stops the run.
#include <gtest/gtest.h>

#include "core/app/runtime/restart_policy.hpp"

namespace rescue::app {
namespace {

constexpr hal::Nanoseconds kMs = hal::kNsPerMs;

RestartPolicy policy() {
  RestartPolicy p;
  p.first_backoff = 100 * kMs;
  p.max_backoff = 400 * kMs;
  p.stable_after = 10 * hal::kNsPerSec;
  return p;
}

TEST(RestartPolicy, RestartableTaskBacksOffDoublingUpToTheCap) {
  hal::VirtualClock clock;
  RestartSchedule s(TaskCriticality::restartable, policy());
  s.started(clock.now());
  const hal::Nanoseconds expected[] = {100 * kMs, 200 * kMs, 400 * kMs, 400 * kMs};
  for (const hal::Nanoseconds backoff : expected) {
    clock.advance(50 * kMs);  // dies soon after each start: a crash loop
    ASSERT_EQ(s.died(clock.now()), DeathVerdict::restart_later);
    EXPECT_EQ(s.last_backoff(), backoff);
    EXPECT_FALSE(s.restart_due(clock.now()));
    clock.advance(backoff - 1);
    EXPECT_FALSE(s.restart_due(clock.now()));
    clock.advance(1);
    EXPECT_TRUE(s.restart_due(clock.now()));
    s.started(clock.now());
    EXPECT_FALSE(s.restart_due(clock.now()));
  }
  EXPECT_EQ(s.restarts(), 4U);
}

TEST(RestartPolicy, ATaskThatRanStablyStartsOverAtTheFirstBackoff) {
  hal::VirtualClock clock;
  RestartSchedule s(TaskCriticality::restartable, policy());
  s.started(clock.now());
  clock.advance(kMs);
  (void)s.died(clock.now());
  clock.sleep_until(s.restart_at());
  s.started(clock.now());
  clock.advance(kMs);
  (void)s.died(clock.now());
  EXPECT_EQ(s.last_backoff(), 200 * kMs);
  clock.sleep_until(s.restart_at());
  s.started(clock.now());
  clock.advance(10 * hal::kNsPerSec);  // ran stably
  (void)s.died(clock.now());
  EXPECT_EQ(s.last_backoff(), 100 * kMs);
}

TEST(RestartPolicy, CriticalTaskDeathStopsTheRunAndIsNeverRestarted) {
  hal::VirtualClock clock;
  RestartSchedule s(TaskCriticality::critical, policy());
  s.started(clock.now());
  clock.advance(kMs);
  EXPECT_EQ(s.died(clock.now()), DeathVerdict::stop_run);
  clock.advance(hal::kNsPerSec * 100);
  EXPECT_FALSE(s.restart_due(clock.now()));
  EXPECT_EQ(s.restarts(), 0U);
}

}  // namespace
}  // namespace rescue::app
