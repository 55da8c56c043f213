// Per-period timing of the firmware's real-time tasks (issue 14; core/timing/period_recorder.hpp):
// each task's loop reads the timer around its period's work and records execution time and wake-up
// latency. Static storage, calibrated once at start-up; written at the end of `run --timing-out DIR`
// as DIR/timing.csv and DIR/timing-histogram.txt (cyclictest --histogram layout).
#pragma once

#include "core/base/result.hpp"
#include "core/timing/period_recorder.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::app {

struct TaskTiming {
  static constexpr std::uint32_t kHistogramMaxUs = 1000;  // one line per microsecond up to a period

  hal::TscTimer timer = hal::TscTimer::monotonic_fallback("not calibrated yet");
  PeriodRecorder handler;
  PeriodRecorder manager;
};

// The run's one instance (static storage, no heap).
TaskTiming& task_timing() noexcept;
// Calibrates the timer (busy-waits 20 ms) and names the recorders; before the tasks start.
void start_task_timing() noexcept;
// Writes DIR/timing.csv and DIR/timing-histogram.txt; prints one summary line per task and figure.
Status write_task_timing(const char* dir) noexcept;

}  // namespace rescue::app
