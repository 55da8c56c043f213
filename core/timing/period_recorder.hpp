// PeriodRecorder: what a periodic real-time task records every period (issue 14): its execution
// time (start to end, TSC ticks converted to ns) and its wake-up latency (release, the instant the
// period was due, to start), each into a fixed LatencyHistogram. No heap, no system call, bounded
// work: two histogram records per period. The task owns its recorder (single writer); read it once
// the task has stopped, or from the same thread.
//
//   per period:   record(latency_ns, start_ticks, end_ticks)
//   end of run:   write_csv(out, recorders)          one row per task and figure
//                 write_cyclictest_histogram(out, recorders)   cyclictest --histogram layout
//
// core/ cannot include hal/: the caller passes the TSC's ns per tick (hal::TscTimer) once.
#pragma once

#include <cstdint>
#include <cstdio>

#include "core/base/span.hpp"
#include "core/timing/latency_histogram.hpp"

namespace rescue {

struct PeriodFigures {
  HistogramSummary summary;
  std::uint64_t p9999{0};  // p99.99
};

// The figures a task publishes live (ctl tasks), in ns, saturated at 2^32 - 1 (4.3 s). Trivial: it
// travels in a seqlock and on the wire (docs/protocol.md, `tasks`).
struct TimingFigures {
  std::uint32_t min;
  std::uint32_t mean;
  std::uint32_t stddev;
  std::uint32_t max;
  std::uint32_t p99;
  std::uint32_t p999;
  std::uint32_t p9999;
};

class PeriodRecorder {
 public:
  // `task` must outlive the recorder (a string literal). `ns_per_tick`: 1 / TscTimer::ticks_per_ns().
  void configure(const char* task, double ns_per_tick) noexcept {
    task_ = task;
    ns_per_tick_ = ns_per_tick;
  }

  // One period: `latency_ns` = start - release on the task's clock (negative counts as 0), and the
  // TSC (or other TscTimer source) readings at the start and the end of the period's work.
  void record(std::int64_t latency_ns, std::uint64_t start_ticks, std::uint64_t end_ticks) noexcept {
    const std::uint64_t ticks = end_ticks >= start_ticks ? end_ticks - start_ticks : 0;
    execution_.record(static_cast<std::uint64_t>(static_cast<double>(ticks) * ns_per_tick_));
    latency_.record(latency_ns > 0 ? static_cast<std::uint64_t>(latency_ns) : 0);
  }

  const char* task() const noexcept { return task_; }
  const LatencyHistogram& execution() const noexcept { return execution_; }
  const LatencyHistogram& latency() const noexcept { return latency_; }
  std::uint64_t periods() const noexcept { return execution_.count(); }
  static PeriodFigures figures(const LatencyHistogram& histogram) noexcept;
  // min, mean, std, max, p99, p99.9, p99.99 in one pass over the buckets (about 2240 additions): cheap
  // enough for a real-time task to publish every hundred periods. No heap, no system call.
  static TimingFigures compact(const LatencyHistogram& histogram) noexcept;
  void reset() noexcept {
    execution_.reset();
    latency_.reset();
  }

  // CSV: "task,figure,unit,count,min,mean,std,max,p50,p99,p99.9,p99.99", one row per task and figure
  // (execution, latency). Returns false when a write failed.
  static bool write_csv(std::FILE* out, Span<const PeriodRecorder* const> recorders) noexcept;
  // cyclictest --histogram layout for the wake-up latency: one line per microsecond
  // "%06u" then one count per task, up to `max_us`, then "# Total:", "# Min Latencies:",
  // "# Avg Latencies:", "# Max Latencies:", "# Histogram Overflows:" (values in us). A histogram
  // bucket wider than 1 us (above 65 us) counts in the microsecond of its lower bound.
  static bool write_cyclictest_histogram(std::FILE* out, Span<const PeriodRecorder* const> recorders,
                                         std::uint32_t max_us) noexcept;

 private:
  LatencyHistogram execution_;
  LatencyHistogram latency_;
  const char* task_{"task"};
  double ns_per_tick_{1.0};
};

}  // namespace rescue
