// The release times of a periodic task, and the task's period loop (docs/tasks.md "Period
// accounting"). Periods are counted from the task's first period (its start-up is not a missed
// period). A period whose work ends after the next release(s) does not make the task run the periods
// it missed back to back (a burst of stale work after a stall): they are skipped, counted as missed
// (not run), and the task goes on at the next release in the same phase. The EtherCAT master keeps
// its own cycle the same way (ecat/master/master_cycle.cpp), so every task's "periods missed" means
// the same: periods that began late plus periods that did not run at all.
#pragma once

#include <atomic>
#include <cstdint>

#include "hal/time/clock.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::app {

class PeriodSchedule {
 public:
  // The first period is due at `first_release`.
  PeriodSchedule(hal::Nanoseconds first_release, hal::Nanoseconds period) noexcept
      : release_(first_release), period_(period > 0 ? period : 1) {}

  // When the current period was due.
  hal::Nanoseconds release() const noexcept { return release_; }
  hal::Nanoseconds period() const noexcept { return period_; }
  // The current period's work ended at `now`: moves to the first release after `now` in the same
  // phase; returns how many releases passed while the work ran (0 when the task kept its period).
  std::uint64_t advance(hal::Nanoseconds now) noexcept {
    release_ += period_;
    if (release_ > now) return 0;
    const auto skipped = static_cast<std::uint64_t>((now - release_) / period_) + 1U;
    release_ += static_cast<hal::Nanoseconds>(skipped) * period_;
    return skipped;
  }

 private:
  hal::Nanoseconds release_;
  hal::Nanoseconds period_;
};

// How every real-time loop wakes for its period (the EtherCAT handler's, `bench latency`'s, `bench
// fig4`'s): sleep until `release` (clock_nanosleep TIMER_ABSTIME on CLOCK_MONOTONIC for the wall
// clock) and read the clock at once, before any work, as cyclictest does; the wake-up latency is the
// result minus `release`.
inline hal::Nanoseconds wake_at(hal::Clock& clock, hal::Nanoseconds release) noexcept {
  clock.sleep_until(release);
  return clock.now();
}

// A periodic task's loop: `work(start)` once per `period` on `clock` until `stop` is set, each period
// recorded in `stats` (`period(due, woke, tsc_before, tsc_after, late_after)`: late when it began more
// than `late_after` after it was due; `skipped(n)`: periods that did not run), and its heartbeat
// (the clock's time at the end of its latest period) stored in `heartbeat` for the supervisor's
// liveness watch. No heap, no system call but the clock's.
template <typename Stats, typename Work>
void run_periods(const std::atomic<bool>& stop, hal::Clock& clock, const hal::TscTimer& timer, hal::Nanoseconds period,
                 hal::Nanoseconds late_after, Stats& stats, std::atomic<std::int64_t>& heartbeat, Work work) noexcept {
  PeriodSchedule schedule(clock.now(), period);
  while (!stop.load(std::memory_order_acquire)) {
    const hal::Nanoseconds start = clock.now();
    const std::uint64_t work_start = timer.start();
    work(start);
    stats.period(schedule.release(), start, work_start, timer.stop(), late_after);
    const hal::Nanoseconds end = clock.now();
    heartbeat.store(end, std::memory_order_release);
    const std::uint64_t skipped = schedule.advance(end);
    if (skipped != 0) stats.skipped(skipped);
    clock.sleep_until(schedule.release());
  }
}

}  // namespace rescue::app
