#include "core/app/runtime/task_timing.hpp"

#include <cinttypes>
#include <cstdio>

namespace rescue::app {

TaskTiming& task_timing() noexcept {
  static TaskTiming timing;
  return timing;
}

void start_task_timing() noexcept {
  TaskTiming& t = task_timing();
  t.timer = hal::TscTimer::calibrate();
  const double ns_per_tick = 1.0 / t.timer.ticks_per_ns();
  t.handler.configure("ethercat", ns_per_tick);
  t.manager.configure("joint_manager", ns_per_tick);
  t.handler.reset();
  t.manager.reset();
}

namespace {

Status write_file(const char* dir, const char* name, bool (*write)(std::FILE*, const TaskTiming&)) noexcept {
  char path[512];
  const int n = std::snprintf(path, sizeof path, "%s/%s", dir, name);
  if (n < 0 || static_cast<std::size_t>(n) >= sizeof path) return make_error(Errc::invalid_argument, "--timing-out path too long");
  std::FILE* out = std::fopen(path, "w");
  if (out == nullptr) return make_error(Errc::io_error, "cannot create the timing file (does the directory exist?)");
  const bool written = write(out, task_timing());
  const bool closed = std::fclose(out) == 0;
  if (!written || !closed) return make_error(Errc::io_error, "cannot write the timing file");
  (void)std::printf("rescue-motion run: timing written to %s\n", path);
  return Status::success();
}

bool write_csv(std::FILE* out, const TaskTiming& t) noexcept {
  const PeriodRecorder* recorders[] = {&t.handler, &t.manager};
  return PeriodRecorder::write_csv(out, Span<const PeriodRecorder* const>(recorders));
}

bool write_histogram(std::FILE* out, const TaskTiming& t) noexcept {
  const PeriodRecorder* recorders[] = {&t.handler, &t.manager};
  return PeriodRecorder::write_cyclictest_histogram(out, Span<const PeriodRecorder* const>(recorders),
                                                    TaskTiming::kHistogramMaxUs);
}

void print_summary(const PeriodRecorder& r) noexcept {
  const PeriodFigures e = PeriodRecorder::figures(r.execution());
  const PeriodFigures l = PeriodRecorder::figures(r.latency());
  (void)std::printf("rescue-motion run: %s: %" PRIu64 " periods; execution min %" PRIu64 " mean %.0f max %" PRIu64
                    " p99.9 %" PRIu64 " ns; wake-up latency min %" PRIu64 " mean %.0f max %" PRIu64 " p99.9 %" PRIu64
                    " ns\n",
                    r.task(), r.periods(), e.summary.min, e.summary.mean, e.summary.max, e.summary.p999, l.summary.min,
                    l.summary.mean, l.summary.max, l.summary.p999);
}

}  // namespace

Status write_task_timing(const char* dir) noexcept {
  print_summary(task_timing().handler);
  print_summary(task_timing().manager);
  RESCUE_TRY(write_file(dir, "timing.csv", write_csv));
  return write_file(dir, "timing-histogram.txt", write_histogram);
}

}  // namespace rescue::app
