#include "core/app/runtime/task_timing.hpp"

#include <unistd.h>

#include <cinttypes>
#include <cstdio>

#include "core/app/operator_protocol/protocol_codec.hpp"
#include "hal/files/trusted_file.hpp"
#include "hal/rt/rt_setup.hpp"

namespace rescue::app {

void TaskRecorder::start(Seqlock<TaskStat>& slot, const char* name, int cpu, int priority, double ns_per_tick) noexcept {
  slot_ = &slot;
  stat_ = TaskStat{};
  protocol::set_text(stat_.name, name);
  stat_.pid = static_cast<std::int32_t>(::getpid());
  stat_.cpu = static_cast<std::int16_t>(cpu);
  stat_.priority = static_cast<std::int16_t>(priority);
  stat_.kernel_policy = -1;
  stat_.kernel_priority = -1;
  stat_.kernel_cpu = -1;
  recorder_.configure(name, ns_per_tick);
  recorder_.reset();
  until_publish_ = 1;
  publish();
}

void TaskRecorder::publish() noexcept {
  if (slot_ == nullptr) return;
  stat_.execution = PeriodRecorder::compact(recorder_.execution());
  stat_.latency = PeriodRecorder::compact(recorder_.latency());
  stat_.max_execution_ns = recorder_.execution().max();
  // What the kernel says of this thread now, not the table's wish (ctl tasks shows both).
  const hal::ThreadSchedule kernel = hal::thread_schedule();
  stat_.kernel_policy = static_cast<std::int8_t>(kernel.policy);
  stat_.kernel_priority = static_cast<std::int16_t>(kernel.priority);
  stat_.kernel_cpu = static_cast<std::int16_t>(kernel.cpu);
  slot_->write(stat_);
}

TaskTiming& task_timing() noexcept {
  static TaskTiming timing;
  return timing;
}

void start_task_timing() noexcept { task_timing().timer = hal::TscTimer::calibrate(); }

namespace {

constexpr std::size_t kMaxRecorders = kTaskStatSlots;

// The recorders of the tasks that ran, in StatTask order.
std::size_t recorders_that_ran(const PeriodRecorder* (&out)[kMaxRecorders]) noexcept {
  std::size_t n = 0;
  for (const TaskRecorder& t : task_timing().tasks) {
    if (t.started()) out[n++] = &t.recorder();
  }
  return n;
}

Status write_file(const char* dir, const char* name, bool (*write)(std::FILE*, Span<const PeriodRecorder* const>)) noexcept {
  char path[512];
  const int n = std::snprintf(path, sizeof path, "%s/%s", dir, name);
  if (n < 0 || static_cast<std::size_t>(n) >= sizeof path) return make_error(Errc::invalid_argument, "--timing-out path too long");
  // A regular file only, never through a link, never a FIFO or device (hal/files/trusted_file.hpp).
  hal::FileProblem why;
  Result<hal::OpenFile> file = hal::open_regular_for_write(path, 0644, why);
  if (!file.ok()) {
    (void)std::fprintf(stderr, "rescue-motion run: --timing-out: %s\n", why.c_str());
    return make_error(Errc::io_error, "cannot create the timing file (does the directory exist?)");
  }
  std::FILE* out = ::fdopen(file.value().fd(), "w");
  if (out == nullptr) return make_error(Errc::io_error, "cannot create the timing file");
  (void)file.value().release();  // the FILE owns it now
  const PeriodRecorder* recorders[kMaxRecorders] = {};
  const std::size_t count = recorders_that_ran(recorders);
  const bool written = write(out, Span<const PeriodRecorder* const>(recorders, count));
  const bool closed = std::fclose(out) == 0;
  if (!written || !closed) return make_error(Errc::io_error, "cannot write the timing file");
  (void)std::printf("rescue-motion run: timing written to %s\n", path);
  return Status::success();
}

bool write_histogram(std::FILE* out, Span<const PeriodRecorder* const> recorders) noexcept {
  return PeriodRecorder::write_cyclictest_histogram(out, recorders, TaskTiming::kHistogramMaxUs);
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
  for (const TaskRecorder& t : task_timing().tasks) {
    if (t.started()) print_summary(t.recorder());
  }
  RESCUE_TRY(write_file(dir, "timing.csv", PeriodRecorder::write_csv));
  return write_file(dir, "timing-histogram.txt", write_histogram);
}

}  // namespace rescue::app
