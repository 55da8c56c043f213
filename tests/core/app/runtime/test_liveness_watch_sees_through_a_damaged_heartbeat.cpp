// The supervisor's liveness watch (core/app/runtime/liveness_watch.hpp) reads heartbeats from the
// shared segment, in virtual time. A damaged beat (core/app/links/heartbeat.hpp: a time far in the
// future, a negative one, a 0 after beats) over a task that has stopped is still reported silent,
// within the limit and two passes, and counted; the same damage over a running task, which rewrites its
// beat the next period, is counted and never reported. Before, a beat from the future hid the silent
// task for good, `now - beat` overflowed on a negative one, and a 0 made the task unwatched.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "core/app/runtime/liveness_watch.hpp"

namespace rescue::app {
namespace {

constexpr hal::Nanoseconds kMs = hal::kNsPerMs;
constexpr auto kHandler = static_cast<std::size_t>(StatTask::ethercat_handler);

// The handler beats every millisecond for 100 ms, checked every 5 ms; then `damage` is written over
// its beat and it either stops (`dead`) or goes on beating. Returns when it was reported silent
// (0: never) within 1 s after the damage.
struct Outcome {
  hal::Nanoseconds reported_after{0};
  std::uint64_t reports{0};
  std::uint64_t damaged{0};
};

Outcome run(std::int64_t damage, bool dead) {
  LivenessWatch::Heartbeats beats{};
  LivenessWatch watch(30 * kMs, 1U << kHandler);
  std::array<LivenessChange, kTaskStatSlots> changes{};
  hal::Nanoseconds now = 1000 * kMs;
  for (int t = 0; t < 100; ++t) {
    now += kMs;
    beats[kHandler].store(now);
    if (t % 5 == 0) (void)watch.check(now, beats, changes);
  }
  const hal::Nanoseconds damaged_at = now;
  beats[kHandler].store(damage);
  Outcome outcome;
  for (int t = 0; t < 1000; ++t) {
    now += kMs;
    if (!dead && t % 5 != 0) beats[kHandler].store(now);  // running: its next period rewrites the beat
    if (t % 5 != 0) continue;
    const std::size_t n = watch.check(now, beats, changes);
    if (n == 1 && changes[0].kind == LivenessChange::Kind::silent && outcome.reported_after == 0) {
      outcome.reported_after = now - damaged_at;
    }
  }
  outcome.reports = watch.reports();
  outcome.damaged = watch.damaged_beats();
  return outcome;
}

TEST(DamagedHeartbeat, ABeatFromTheFutureOverAStoppedTaskIsReportedSilent) {
  const Outcome o = run(std::numeric_limits<std::int64_t>::max() / 2, true);
  EXPECT_EQ(o.reports, 1U);
  EXPECT_GT(o.reported_after, 30 * kMs);
  // A whole beat would be reported one pass after the limit; a damaged one, whose age is how long it
  // has not moved since the watch first saw it, one pass later.
  EXPECT_LE(o.reported_after, 40 * kMs) << "within the limit plus two passes";
  EXPECT_EQ(o.damaged, 1U);
}

TEST(DamagedHeartbeat, ANegativeBeatOverAStoppedTaskIsReportedSilent) {
  const Outcome o = run(std::numeric_limits<std::int64_t>::min(), true);
  EXPECT_EQ(o.reports, 1U);
  EXPECT_GT(o.reported_after, 30 * kMs);
  EXPECT_LE(o.reported_after, 40 * kMs);
  EXPECT_EQ(o.damaged, 1U);
}

TEST(DamagedHeartbeat, AZeroAfterBeatsOverAStoppedTaskIsReportedSilent) {
  const Outcome o = run(0, true);
  EXPECT_EQ(o.reports, 1U);
  EXPECT_GT(o.reported_after, 30 * kMs);
  EXPECT_LE(o.reported_after, 40 * kMs);
  EXPECT_EQ(o.damaged, 1U);
}

TEST(DamagedHeartbeat, DamageOverARunningTaskIsCountedNeverReported) {
  for (const std::int64_t damage : {std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min(),
                                    std::int64_t{-1}, std::int64_t{0}}) {
    const Outcome o = run(damage, false);
    EXPECT_EQ(o.reports, 0U) << damage;
    EXPECT_EQ(o.damaged, 1U) << damage;
  }
}

TEST(DamagedHeartbeat, ABeatJustAheadOfTheReadersClockIsWhole) {
  // The writer beat after the reader read its clock: taken as now, not counted.
  EXPECT_EQ(heartbeat_age(1000 * kMs, 1000 * kMs + kHeartbeatAheadLimitNs).kind, HeartbeatAge::Kind::whole);
  EXPECT_EQ(heartbeat_age(1000 * kMs, 1000 * kMs + kHeartbeatAheadLimitNs).age, 0);
  EXPECT_EQ(heartbeat_age(1000 * kMs, 1000 * kMs + kHeartbeatAheadLimitNs + 1).kind, HeartbeatAge::Kind::damaged);
  EXPECT_EQ(heartbeat_age(1000 * kMs, 990 * kMs).age, 10 * kMs);
  EXPECT_EQ(heartbeat_age(1000 * kMs, 0).kind, HeartbeatAge::Kind::never);
}

}  // namespace
}  // namespace rescue::app
