// TaskRecorder (core/app/runtime/task_timing.hpp), the one timing mechanism of the firmware's task
// loops: every period lands in the PeriodRecorder's histograms, late periods are counted, and the
// seqlock slot `ctl tasks` reads carries, live, the periods, the late periods and the histograms'
// min, mean, std, max, p99, p99.9 and p99.99 of execution time and wake-up latency; compact figures
// equal the histogram's own percentiles; recording and publishing allocate nothing (heap guard strict).
#include <gtest/gtest.h>

#include "core/app/links/control_messages.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/memory/heap_guard.hpp"

namespace rescue::app {
namespace {

TEST(TaskRecorder, PublishesEveryFigureLiveWithoutHeap) {
  static Seqlock<TaskStat> slot;
  static TaskRecorder recorder;
  recorder.start(slot, "ethercat", 3, 80, 1.0);  // 1 tick = 1 ns
  TaskStat seen{};
  ASSERT_TRUE(slot.try_read(seen));
  EXPECT_STREQ(seen.name.data(), "ethercat");
  EXPECT_EQ(seen.periods, 0U);

  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);
  constexpr hal::Nanoseconds kLateAfter = 500'000;
  for (std::int64_t i = 0; i < 10'000; ++i) {
    const hal::Nanoseconds release = i * 1'000'000;
    // wake-up latency 10 us, except two late periods (600 us); execution 1000..1099 ns.
    const hal::Nanoseconds woke = release + (i == 7000 || i == 8000 ? 600'000 : 10'000);
    const auto t0 = static_cast<std::uint64_t>(woke);
    recorder.period(release, woke, t0, t0 + 1000 + static_cast<std::uint64_t>(i % 100), kLateAfter);
    if (i == static_cast<std::int64_t>(TaskRecorder::kPublishEvery) + 50) {  // mid-run: last published after period 1000
      ASSERT_TRUE(slot.try_read(seen));
      EXPECT_EQ(seen.periods, TaskRecorder::kPublishEvery);
      EXPECT_EQ(seen.execution.min, 1000U);
      EXPECT_EQ(seen.latency.max, 10'000U);
    }
  }
  recorder.publish();
  const HeapGuardCounters heap = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(heap.allocations, 0U);

  ASSERT_TRUE(slot.try_read(seen));
  EXPECT_EQ(seen.periods, 10'000U);
  EXPECT_EQ(seen.missed, 2U);
  EXPECT_EQ(recorder.missed(), 2U);
  EXPECT_EQ(seen.execution.min, 1000U);
  EXPECT_EQ(seen.execution.max, 1099U);
  EXPECT_EQ(seen.max_execution_ns, 1099U);
  EXPECT_NEAR(seen.execution.mean, 1049.5, 1.0);
  EXPECT_NEAR(seen.execution.stddev, 28.9, 1.0);  // uniform over 100 values: sqrt((100^2 - 1) / 12)
  const LatencyHistogram& e = recorder.recorder().execution();
  EXPECT_EQ(seen.execution.p99, e.percentile(99.0));
  EXPECT_EQ(seen.execution.p999, e.percentile(99.9));
  EXPECT_EQ(seen.execution.p9999, e.percentile(99.99));
  EXPECT_EQ(seen.latency.min, 10'000U);
  EXPECT_EQ(seen.latency.max, 600'000U);
  EXPECT_EQ(seen.latency.p9999, 600'000U);  // 2 in 10 000: p99.99 reaches them
  EXPECT_LE(seen.latency.p999, 10'000U + 10'000U / 64U);
  EXPECT_EQ(recorder.recorder().periods(), 10'000U);
}

// `ctl tasks` early in a run: the slot is published after periods 1, 10, 100 and 1000, then every
// kPublishEvery periods, and at no other period (the period itself only counts down).
TEST(TaskRecorder, PublishesAfterPeriods1And10And100ThenEvery1000) {
  static Seqlock<TaskStat> slot;
  static TaskRecorder recorder;
  recorder.start(slot, "rc-rescue", 0, 65, 1.0);
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);
  std::uint64_t published[16] = {};
  std::size_t publications = 0;
  std::uint64_t last_seen = 0;
  for (std::int64_t i = 0; i < 3500; ++i) {
    const hal::Nanoseconds release = i * 1'000'000;
    const auto t0 = static_cast<std::uint64_t>(release);
    recorder.period(release, release + 5'000, t0, t0 + 2'000, 500'000);
    TaskStat seen{};
    if (slot.try_read(seen) && seen.periods != last_seen && publications < 16) {
      last_seen = seen.periods;
      published[publications++] = seen.periods;
    }
  }
  const HeapGuardCounters heap = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(heap.allocations, 0U);
  const std::uint64_t expected[] = {1, 10, 100, 1000, 2000, 3000};
  ASSERT_EQ(publications, 6U);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(published[k], expected[k]) << k;
  static_assert(TaskRecorder::periods_until_next_publication(1) == 9, "after period 1, period 10");
  static_assert(TaskRecorder::periods_until_next_publication(100) == 900, "after period 100, period 1000");
  static_assert(TaskRecorder::periods_until_next_publication(1000) == TaskRecorder::kPublishEvery, "then steady");
}

TEST(TaskRecorder, OnePassPercentilesEqualThePercentilesOneByOne) {
  static LatencyHistogram h;
  h.reset();
  for (std::uint64_t v = 1; v <= 100'000; ++v) h.record((v * 7919) % 1'000'003);
  const double percents[] = {0.0, 50.0, 99.0, 99.9, 99.99, 100.0};
  std::uint64_t out[6] = {};
  h.percentiles(percents, out, 6);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(out[i], h.percentile(percents[i])) << percents[i];
  LatencyHistogram empty;
  empty.percentiles(percents, out, 6);
  for (const std::uint64_t v : out) EXPECT_EQ(v, 0U);
}

}  // namespace
}  // namespace rescue::app
