// The supervisor's liveness watch (core/app/runtime/liveness_watch.hpp), in virtual time: a watched
// task whose heartbeat is older than the limit is reported once (with its age), not again while it
// stays silent, and reported again when it completes a period (with how long it was silent); a task
// before its first period, or not watched, is never reported. Issue 21 item 5.
#include <gtest/gtest.h>

#include "core/app/runtime/liveness_watch.hpp"

namespace rescue::app {
namespace {

constexpr hal::Nanoseconds kMs = hal::kNsPerMs;
constexpr auto kHandler = static_cast<std::size_t>(StatTask::ethercat_handler);
constexpr auto kManager = static_cast<std::size_t>(StatTask::joint_manager);
constexpr auto kParser = static_cast<std::size_t>(StatTask::message_parser);

TEST(LivenessWatch, ReportsASilentTaskOnceAndItsReturn) {
  LivenessWatch::Heartbeats beats{};
  LivenessWatch watch(30 * kMs, (1U << kHandler) | (1U << kManager));
  std::array<LivenessChange, kTaskStatSlots> changes{};
  // Both run every millisecond for 100 ms, checked every 5 ms (the supervisor's pass): nothing.
  hal::Nanoseconds now = 1000 * kMs;
  for (int t = 0; t < 100; ++t) {
    now += kMs;
    beats[kHandler].store(now);
    beats[kManager].store(now);
    if (t % 5 == 0) {
      EXPECT_EQ(watch.check(now, beats, changes), 0U) << t;
    }
  }
  // The handler stops (SIGSTOP) for 1 s after its period at `stopped`; the joint manager goes on.
  const hal::Nanoseconds stopped = now;
  std::size_t reported = 0;
  hal::Nanoseconds reported_at = 0;
  for (int t = 0; t < 1000; ++t) {
    now += kMs;
    beats[kManager].store(now);
    if (t % 5 != 4) continue;
    const std::size_t n = watch.check(now, beats, changes);
    if (n == 0) continue;
    ASSERT_EQ(n, 1U);
    EXPECT_EQ(changes[0].kind, LivenessChange::Kind::silent);
    EXPECT_EQ(changes[0].task, kHandler);
    EXPECT_EQ(changes[0].silent_ns, now - stopped);
    ++reported;
    reported_at = now;
  }
  EXPECT_EQ(reported, 1U) << "once per silence";
  EXPECT_GT(reported_at - stopped, 30 * kMs);
  EXPECT_LE(reported_at - stopped, 35 * kMs) << "within the limit plus one pass";
  EXPECT_TRUE(watch.silent(kHandler));
  EXPECT_FALSE(watch.silent(kManager));
  // It runs again.
  now += kMs;
  beats[kHandler].store(now);
  ASSERT_EQ(watch.check(now, beats, changes), 1U);
  EXPECT_EQ(changes[0].kind, LivenessChange::Kind::resumed);
  EXPECT_EQ(changes[0].silent_ns, now - stopped);
  EXPECT_FALSE(watch.silent(kHandler));
  EXPECT_EQ(watch.reports(), 1U);
}

TEST(LivenessWatch, NeverReportsATaskBeforeItsFirstPeriodOrOneNotWatched) {
  LivenessWatch::Heartbeats beats{};
  LivenessWatch watch(30 * kMs, 1U << kHandler);
  std::array<LivenessChange, kTaskStatSlots> changes{};
  beats[kParser].store(1);  // not watched: silent for ever
  EXPECT_EQ(watch.check(10 * hal::kNsPerSec, beats, changes), 0U);  // the handler never beat
  EXPECT_EQ(watch.reports(), 0U);
}

}  // namespace
}  // namespace rescue::app
