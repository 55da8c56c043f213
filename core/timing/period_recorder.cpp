#include "core/timing/period_recorder.hpp"

#include <cinttypes>
#include <cmath>

namespace rescue {
namespace {

constexpr std::uint64_t kNsPerUs = 1000;

}  // namespace

PeriodFigures PeriodRecorder::figures(const LatencyHistogram& histogram) noexcept {
  PeriodFigures f;
  f.summary = histogram.summary();
  f.p9999 = histogram.percentile(99.99);
  return f;
}

namespace {

std::uint32_t saturate(double v) noexcept {
  if (!(v > 0.0)) return 0;
  return v >= 4294967295.0 ? 0xFFFFFFFFU : static_cast<std::uint32_t>(std::llround(v));
}

}  // namespace

TimingFigures PeriodRecorder::compact(const LatencyHistogram& histogram) noexcept {
  static constexpr double kPercents[] = {99.0, 99.9, 99.99};
  std::uint64_t tail[3] = {0, 0, 0};
  histogram.percentiles(kPercents, tail, 3);
  TimingFigures f{};
  f.min = saturate(static_cast<double>(histogram.min()));
  f.mean = saturate(histogram.mean());
  f.stddev = saturate(histogram.stddev());
  f.max = saturate(static_cast<double>(histogram.max()));
  f.p99 = saturate(static_cast<double>(tail[0]));
  f.p999 = saturate(static_cast<double>(tail[1]));
  f.p9999 = saturate(static_cast<double>(tail[2]));
  return f;
}

bool PeriodRecorder::write_csv(std::FILE* out, Span<const PeriodRecorder* const> recorders) noexcept {
  bool ok = std::fprintf(out, "task,figure,unit,count,min,mean,std,max,p50,p99,p99.9,p99.99\n") > 0;
  for (const PeriodRecorder* r : recorders) {
    const LatencyHistogram* histograms[] = {&r->execution_, &r->latency_};
    const char* names[] = {"execution", "wakeup_latency"};
    for (std::size_t i = 0; i < 2; ++i) {
      const PeriodFigures f = figures(*histograms[i]);
      ok = std::fprintf(out, "%s,%s,ns,%" PRIu64 ",%" PRIu64 ",%.1f,%.1f,%" PRIu64 ",%" PRIu64 ",%" PRIu64 ",%" PRIu64
                        ",%" PRIu64 "\n",
                        r->task_, names[i], f.summary.count, f.summary.min, f.summary.mean, f.summary.stddev,
                        f.summary.max, f.summary.p50, f.summary.p99, f.summary.p999, f.p9999) > 0 &&
           ok;
    }
  }
  return ok;
}

bool PeriodRecorder::write_cyclictest_histogram(std::FILE* out, Span<const PeriodRecorder* const> recorders,
                                                std::uint32_t max_us) noexcept {
  bool ok = std::fprintf(out, "# rescue-motion wake-up latency histogram (cyclictest --histogram layout), us\n") > 0;
  ok = std::fprintf(out, "# tasks:") > 0 && ok;
  for (const PeriodRecorder* r : recorders) ok = std::fprintf(out, " %s", r->task_) > 0 && ok;
  ok = std::fprintf(out, "\n") > 0 && ok;
  // Walk every task's buckets once per microsecond line: bucket b counts in us = lower(b) / 1000.
  constexpr std::size_t kMaxTasks = 16;
  std::size_t next[kMaxTasks] = {};
  const std::size_t tasks = recorders.size() < kMaxTasks ? recorders.size() : kMaxTasks;
  for (std::uint32_t us = 0; us < max_us; ++us) {
    ok = std::fprintf(out, "%06u", us) > 0 && ok;
    // cppcheck follows a caller with no recorders and calls this always false; other callers pass some.
    // cppcheck-suppress knownConditionTrueFalse
    for (std::size_t t = 0; t < tasks; ++t) {
      const LatencyHistogram& h = recorders[t]->latency_;
      std::uint64_t count = 0;
      while (next[t] < LatencyHistogram::kBucketCount &&
             LatencyHistogram::bucket_lower(next[t]) / kNsPerUs == us) {
        count += h.count_in(next[t]);
        ++next[t];
      }
      ok = std::fprintf(out, " %06" PRIu64, count) > 0 && ok;
    }
    ok = std::fprintf(out, "\n") > 0 && ok;
  }
  const char* labels[] = {"# Total:", "# Min Latencies:", "# Avg Latencies:", "# Max Latencies:", "# Histogram Overflows:"};
  for (std::size_t line = 0; line < 5; ++line) {
    ok = std::fprintf(out, "%s", labels[line]) > 0 && ok;
    // cppcheck follows a caller with no recorders and calls this always false; other callers pass some.
    // cppcheck-suppress knownConditionTrueFalse
    for (std::size_t t = 0; t < tasks; ++t) {
      const LatencyHistogram& h = recorders[t]->latency_;
      std::uint64_t value = 0;
      switch (line) {
        case 0: value = h.count(); break;
        case 1: value = h.min() / kNsPerUs; break;
        case 2: value = static_cast<std::uint64_t>(h.mean()) / kNsPerUs; break;
        case 3: value = h.max() / kNsPerUs; break;
        default: {
          std::uint64_t over = 0;
          for (std::size_t b = next[t]; b < LatencyHistogram::kBucketCount; ++b) over += h.count_in(b);
          value = over;
        }
      }
      ok = std::fprintf(out, " %06" PRIu64, value) > 0 && ok;
    }
    ok = std::fprintf(out, "\n") > 0 && ok;
  }
  return ok;
}

}  // namespace rescue
