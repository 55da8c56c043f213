// The periodic tasks' loop (core/app/runtime/period_schedule.hpp), in virtual time: periods are
// counted from the task's first period; a period whose work outlasts later releases (a stall) does
// not make the task run the missed periods back to back afterwards: they are skipped, counted as
// missed, and the task goes on at the next release in the same phase. The heartbeat is the end of the
// latest period. Issue 21 item 4 (a 1 s stall of a task was followed by 1000 periods back to back).
#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "core/app/links/control_messages.hpp"
#include "core/app/runtime/period_schedule.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/concurrency/seqlock.hpp"

namespace rescue::app {
namespace {

constexpr hal::Nanoseconds kPeriod = hal::kNsPerMs;

TEST(PeriodSchedule, KeepsThePhaseAndCountsTheReleasesAWorkOutlasted) {
  PeriodSchedule s(5 * kPeriod + 300, kPeriod);
  EXPECT_EQ(s.release(), 5 * kPeriod + 300);
  EXPECT_EQ(s.advance(5 * kPeriod + 900), 0U);  // on time
  EXPECT_EQ(s.release(), 6 * kPeriod + 300);
  EXPECT_EQ(s.advance(7 * kPeriod + 300), 1U);  // ended exactly at the next release: that one passed
  EXPECT_EQ(s.release(), 8 * kPeriod + 300);
  EXPECT_EQ(s.advance(8 * kPeriod + 300 + 3 * kPeriod + 5), 3U);
  EXPECT_EQ(s.release(), 12 * kPeriod + 300);
}

TEST(PeriodLoop, AStallIsSkippedAndCountedNotRunBackToBack) {
  static Seqlock<TaskStat> slot;
  static TaskRecorder recorder;
  recorder.start(slot, "joint-manager", 1, 70, 1.0);
  hal::VirtualClock clock(hal::kNsPerSec);
  const hal::TscTimer timer = hal::TscTimer::monotonic_fallback("test");
  std::atomic<bool> stop{false};
  std::atomic<std::int64_t> heartbeat{0};
  std::vector<hal::Nanoseconds> starts;
  const hal::Nanoseconds first = clock.now();
  run_periods(stop, clock, timer, kPeriod, kPeriod / 2, recorder, heartbeat, [&](hal::Nanoseconds start) noexcept {
    starts.push_back(start);
    clock.advance(100 * hal::kNsPerUs);  // the period's work
    if (starts.size() == 10) clock.advance(hal::kNsPerSec);  // stalled 1 s in its 10th period
    if (starts.size() == 30) stop.store(true);
  });
  ASSERT_EQ(starts.size(), 30U);
  // Never back to back: every period starts at its own release, a whole number of periods apart.
  for (std::size_t i = 1; i < starts.size(); ++i) {
    EXPECT_GE(starts[i] - starts[i - 1], kPeriod) << "period " << i;
    EXPECT_EQ((starts[i] - first) % kPeriod, 0) << "period " << i << " out of phase";
  }
  // The 1 s stall plus the rest of its own period: its 1000 following releases passed without a run.
  EXPECT_EQ(starts[10] - starts[9], 1001 * kPeriod);
  recorder.publish();
  TaskStat stat{};
  ASSERT_TRUE(slot.try_read(stat));
  EXPECT_EQ(stat.periods, 30U);
  EXPECT_EQ(stat.missed, 1000U) << "the periods not run; the first period is not late (counted from the task's start)";
  EXPECT_EQ(heartbeat.load(), starts.back() + 100 * hal::kNsPerUs) << "the end of the latest period";
}

}  // namespace
}  // namespace rescue::app
