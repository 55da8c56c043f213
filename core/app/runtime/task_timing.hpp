// Per-period timing of the firmware's tasks (issue 14), one mechanism for everything: each task's
// loop reads the timer (TSC) around its period's work and hands it, with the period's release and
// wake-up instants, to its TaskRecorder, which
//   - records execution time and wake-up latency (release to start) into its PeriodRecorder's fixed
//     histograms (core/timing/period_recorder.hpp): static storage, no heap, no system call;
//   - counts periods and missed periods: those that woke more than `late_after` after their release,
//     and those that did not run at all (skipped after a stall, `skipped`; period_schedule.hpp);
//   - after periods 1, 10, 100 and 1000, then every kPublishEvery periods, publishes them with the
//     histograms' min, mean, std, max, p99, p99.9, p99.99 (PeriodRecorder::compact: one pass over the buckets) into the task's TaskStat
//     seqlock slot (TaskLinks::task_stats), which the socket handler answers `ctl tasks` from, live.
// At the end of `run --timing-out DIR` the same recorders are written as DIR/timing.csv and
// DIR/timing-histogram.txt (cyclictest --histogram layout).
#pragma once

#include <array>
#include <cstdint>

#include "core/app/links/task_links.hpp"
#include "core/base/result.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/timing/period_recorder.hpp"
#include "hal/time/clock.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::app {

class TaskRecorder {
 public:
  // Periods between publications in the slot: 1 s at 1 kHz (`ctl tasks` is read by people). The
  // publication's pass over the buckets (up to the p99.99 bucket, about 1 us for 100 us values)
  // then costs about 1 ns a period.
  static constexpr std::uint32_t kPublishEvery = 1000;
  // The first publications come sooner, after periods 1, 10 and 100 (then 1000, 2000, ...), so that
  // `ctl tasks` in a run's first second shows more than the first period. The schedule is computed
  // at a publication; the period itself still only counts down.
  static constexpr std::uint32_t periods_until_next_publication(std::uint64_t periods_published) noexcept {
    return periods_published != 0 && periods_published < kPublishEvery
               ? static_cast<std::uint32_t>(periods_published * 9U)  // 1 -> 10 -> 100 -> 1000
               : kPublishEvery;
  }

  // Before the task's first period (from the task's thread or before it starts): names the task,
  // resets the histograms and publishes an empty record.
  void start(Seqlock<TaskStat>& slot, const char* name, int cpu, int priority, double ns_per_tick) noexcept;
  // One period: due at `due_ns`, begun at `woke_ns` (the task's clock), its work between the timer
  // readings `tsc_before` and `tsc_after`; late when woke_ns - due_ns > late_after.
  void period(hal::Nanoseconds due_ns, hal::Nanoseconds woke_ns, std::uint64_t tsc_before, std::uint64_t tsc_after,
              hal::Nanoseconds late_after) noexcept {
    recorder_.record(woke_ns - due_ns, tsc_before, tsc_after);
    ++stat_.periods;
    if (woke_ns - due_ns > late_after) ++stat_.missed;
    if (--until_publish_ == 0) {
      until_publish_ = periods_until_next_publication(stat_.periods);
      publish();
    }
  }
  // `count` periods did not run at all (their releases passed during a late or long period, and the
  // task went on at the next release instead of running them back to back): missed, not run.
  void skipped(std::uint64_t count) noexcept { stat_.missed += count; }
  // Publishes the figures now (at the end of the task, or for a test).
  void publish() noexcept;

  std::uint64_t missed() const noexcept { return stat_.missed; }
  const PeriodRecorder& recorder() const noexcept { return recorder_; }
  bool started() const noexcept { return slot_ != nullptr; }

 private:
  PeriodRecorder recorder_;
  Seqlock<TaskStat>* slot_{nullptr};
  TaskStat stat_{};
  std::uint32_t until_publish_{1};  // the first period publishes
};

struct TaskTiming {
  static constexpr std::uint32_t kHistogramMaxUs = 1000;  // one line per microsecond up to a period

  hal::TscTimer timer = hal::TscTimer::monotonic_fallback("not calibrated yet");
  std::array<TaskRecorder, kTaskStatSlots> tasks;  // indexed by StatTask

  TaskRecorder& operator[](StatTask task) noexcept { return tasks[static_cast<std::size_t>(task)]; }
  double ns_per_tick() const noexcept { return 1.0 / timer.ticks_per_ns(); }
};

// The run's one instance (static storage, no heap).
TaskTiming& task_timing() noexcept;
// Calibrates the timer (busy-waits 20 ms); before the tasks start.
void start_task_timing() noexcept;
// Writes DIR/timing.csv and DIR/timing-histogram.txt for every task that recorded; prints one
// summary line per task.
Status write_task_timing(const char* dir) noexcept;

}  // namespace rescue::app
