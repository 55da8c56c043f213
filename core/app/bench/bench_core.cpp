#include "core/app/bench/bench_core.hpp"

#include <atomic>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <thread>

#include "core/app/bench/bench_header.hpp"
#include "core/app/runtime/task_timing.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/timing/latency_histogram.hpp"
#include "core/timing/period_recorder.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/concurrency/spsc_queue.hpp"
#include "hal/time/clock.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::app {
namespace {

constexpr std::uint64_t kTimerPairs = 1'000'000;
constexpr std::uint64_t kClockBatches = 10'000;
constexpr std::uint64_t kClockBatch = 100;
constexpr std::uint64_t kRoundTrips = 100'000;
constexpr std::uint64_t kThroughputMessages = 1'000'000;
constexpr std::uint64_t kSeqlockOps = 1'000'000;

struct Message {
  std::uint64_t sequence;
  std::uint64_t payload[3];  // 32 bytes: a joint command's size
};
struct Snapshot {
  std::int64_t words[8];  // 64 bytes: a joint state record
};

// Static: 18 KiB each, touched (reset) before init so they never fault afterwards.
LatencyHistogram g_timer_ticks;
LatencyHistogram g_clock_ns;
LatencyHistogram g_round_trip_ns;
LatencyHistogram g_record_probe;
TaskRecorder g_period_probe;  // the task loops' recorder (runtime/task_timing.hpp)
Seqlock<TaskStat> g_probe_slot;
TaskRecorder g_publish_probe;
LatencyHistogram g_publish_ns;
LatencyHistogram g_period_ns;
SpscQueue<Message, 1024> g_ping;
SpscQueue<Message, 1024> g_pong;
Seqlock<Snapshot> g_snapshot;

enum class Phase : int { echo, drain, stop };
std::atomic<Phase> g_phase{Phase::echo};
std::atomic<std::uint64_t> g_drained{0};

// The second thread: echoes pings, then drains the throughput stream.
void partner() noexcept {
  Message m{};
  std::uint64_t drained = 0;
  for (;;) {
    const Phase phase = g_phase.load(std::memory_order_acquire);
    if (phase == Phase::stop) return;
    if (!g_ping.try_pop(m)) continue;
    if (phase == Phase::echo) {
      while (!g_pong.try_push(m)) {
      }
    } else {
      g_drained.store(++drained, std::memory_order_relaxed);  // a plain store: no locked RMW per message
    }
  }
}

double per_op_ns(const hal::TscTimer& timer, std::uint64_t ticks, std::uint64_t ops) noexcept {
  return static_cast<double>(timer.to_ns(ticks)) / static_cast<double>(ops);
}

}  // namespace

namespace {

// The measured parts of bench_core, in its order; nothing in them may allocate.
struct CoreTicks {
  std::uint64_t stream{0};         // kThroughputMessages through the queue to the partner thread
  std::uint64_t seqlock_write{0};  // kSeqlockOps writes
  std::uint64_t seqlock_read{0};   // kSeqlockOps reads
  std::uint64_t read_failures{0};
  std::uint64_t record{0};         // kSeqlockOps histogram records
};

void measure_timer_and_clock(const hal::TscTimer& timer) noexcept {
  for (std::uint64_t i = 0; i < kTimerPairs; ++i) {
    const std::uint64_t start = timer.start();
    g_timer_ticks.record(timer.stop() - start);
  }

  hal::MonotonicClock clock;
  for (std::uint64_t b = 0; b < kClockBatches; ++b) {
    const std::uint64_t start = timer.start();
    for (std::uint64_t i = 0; i < kClockBatch; ++i) (void)clock.now();
    g_clock_ns.record(static_cast<std::uint64_t>(timer.to_ns(timer.stop() - start)) / kClockBatch);
  }
}

std::uint64_t measure_queues(const hal::TscTimer& timer) noexcept {
  Message m{};
  for (std::uint64_t i = 0; i < kRoundTrips; ++i) {
    const std::uint64_t start = timer.start();
    m.sequence = i;
    while (!g_ping.try_push(m)) {
    }
    while (!g_pong.try_pop(m)) {
    }
    g_round_trip_ns.record(static_cast<std::uint64_t>(timer.to_ns(timer.stop() - start)));
  }

  g_phase.store(Phase::drain, std::memory_order_release);
  const std::uint64_t stream_start = timer.start();
  for (std::uint64_t i = 0; i < kThroughputMessages; ++i) {
    m.sequence = i;
    while (!g_ping.try_push(m)) {
    }
  }
  while (g_drained.load(std::memory_order_relaxed) < kThroughputMessages) {
  }
  const std::uint64_t stream_ticks = timer.stop() - stream_start;
  return stream_ticks;
}

void measure_seqlock_and_histogram(const hal::TscTimer& timer, CoreTicks& ticks) noexcept {
  Snapshot s{};
  const std::uint64_t write_start = timer.start();
  for (std::uint64_t i = 0; i < kSeqlockOps; ++i) {
    s.words[0] = static_cast<std::int64_t>(i);
    g_snapshot.write(s);
  }
  const std::uint64_t write_ticks = timer.stop() - write_start;
  std::uint64_t read_failures = 0;
  const std::uint64_t read_start = timer.start();
  for (std::uint64_t i = 0; i < kSeqlockOps; ++i) {
    if (!g_snapshot.try_read(s)) ++read_failures;
  }
  const std::uint64_t read_ticks = timer.stop() - read_start;

  const std::uint64_t record_start = timer.start();
  for (std::uint64_t i = 0; i < kSeqlockOps; ++i) g_record_probe.record(i & 0xFFFFU);
  const std::uint64_t record_ticks = timer.stop() - record_start;
  ticks.seqlock_write = write_ticks;
  ticks.seqlock_read = read_ticks;
  ticks.read_failures = read_failures;
  ticks.record = record_ticks;
}

void measure_period_recording(const hal::TscTimer& timer) noexcept {
  // What the firmware's task loops add per period (runtime/task_loops.cpp, task_timing.hpp): the timer read
  // before and after the work, and TaskRecorder::period: the two histogram records, the late-period
  // count and the countdown to the next publication of the live figures (every
  // TaskRecorder::kPublishEvery periods, measured on its own below). The loops' clock reads were
  // there before.
  // Batches of kClockBatch, each timed as a whole: the median batch is not hit by preemption.
  for (std::uint64_t b = 0; b < kClockBatches; ++b) {
    const std::uint64_t batch_start = timer.start();
    for (std::uint64_t i = 0; i < kClockBatch; ++i) {
      const std::uint64_t work_start = timer.start();
      const std::uint64_t work_end = timer.stop();
      g_period_probe.period(0, static_cast<hal::Nanoseconds>(i), work_start, work_end, hal::kNsPerMs / 2);
    }
    g_period_ns.record(static_cast<std::uint64_t>(timer.to_ns(timer.stop() - batch_start)) / kClockBatch);
  }

  // The publication alone (PeriodRecorder::compact of both histograms, one seqlock write), on
  // histograms holding what the handler records with the simulated robot (execution 85..120 us,
  // wake-up latency 10..400 us): the pass over the buckets ends at the p99.99 bucket.
  g_publish_probe.start(g_probe_slot, "publish", -1, 0, 1.0);
  for (std::uint64_t i = 0; i < 10'000; ++i) {
    const std::uint64_t start = 1'000'000 * i;
    g_publish_probe.period(0, static_cast<hal::Nanoseconds>(10'000 + (i * 7919) % 390'000), start,
                           start + 85'000 + (i * 104'729) % 35'000, hal::kNsPerMs / 2);
  }
  for (std::uint64_t b = 0; b < 1000; ++b) {
    const std::uint64_t publish_start = timer.start();
    g_publish_probe.publish();
    g_publish_ns.record(static_cast<std::uint64_t>(timer.to_ns(timer.stop() - publish_start)));
  }
}

void print_core_figures(const hal::TscTimer& timer, const CoreTicks& ticks) noexcept {
  (void)std::printf("timer_source: %s\n", hal::to_string(timer.source()));
  (void)std::printf("timer_reason: %s\n", timer.reason());
  (void)std::printf("timer_ticks_per_ns: %.4f ticks/ns\n", timer.ticks_per_ns());
  g_timer_ticks.print(stdout, "timer_overhead", "ticks");
  (void)std::printf("timer_overhead_p50_ns: %" PRId64 " ns\n", timer.to_ns(g_timer_ticks.percentile(50.0)));
  (void)std::printf("clock_gettime_p50: %" PRIu64 " ns\n", g_clock_ns.percentile(50.0));
  g_round_trip_ns.print(stdout, "spsc_round_trip", "ns");
  (void)std::printf("spsc_throughput: %.1f Mmsg/s\n",
                    1e3 * static_cast<double>(kThroughputMessages) / static_cast<double>(timer.to_ns(ticks.stream)));
  (void)std::printf("seqlock_write: %.1f ns\n", per_op_ns(timer, ticks.seqlock_write, kSeqlockOps));
  (void)std::printf("seqlock_read: %.1f ns\n", per_op_ns(timer, ticks.seqlock_read, kSeqlockOps));
  (void)std::printf("seqlock_read_failures: %" PRIu64 " reads\n", ticks.read_failures);
  (void)std::printf("histogram_record: %.1f ns\n", per_op_ns(timer, ticks.record, kSeqlockOps));
  (void)std::printf("period_recording_p50: %" PRIu64 " ns\n", g_period_ns.percentile(50.0));
  (void)std::printf("period_recording_p90: %" PRIu64 " ns\n", g_period_ns.percentile(90.0));
  (void)std::printf("task_figures_publish_p50: %" PRIu64 " ns\n", g_publish_ns.percentile(50.0));
}

}  // namespace

int bench_core(const ParsedArgs& /*args*/) noexcept {
  // ---- init: everything that may allocate or fault ----
  print_bench_header(stdout, "core");
  hal::RtConfig rt;
  rt.prefault_stack_bytes = std::size_t{256} * 1024;
  const hal::RtReport report = hal::apply_rt_config(rt);
  report.print(stdout);
  const hal::TscTimer timer = hal::TscTimer::calibrate();
  g_timer_ticks.reset();
  g_clock_ns.reset();
  g_round_trip_ns.reset();
  g_record_probe.reset();
  g_period_probe.start(g_probe_slot, "probe", -1, 0, 1.0 / timer.ticks_per_ns());
  g_period_ns.reset();
  std::thread second(partner);
  (void)std::fflush(stdout);
  const hal::PageFaults faults_at_init = hal::page_faults_of_process();
  declare_init_complete(HeapGuardMode::count);

  // ---- measured: nothing below may allocate ----
  CoreTicks ticks;
  measure_timer_and_clock(timer);
  ticks.stream = measure_queues(timer);
  measure_seqlock_and_histogram(timer, ticks);
  measure_period_recording(timer);
  const HeapGuardCounters heap = heap_guard_counters();
  const hal::PageFaults faults_after = hal::page_faults_of_process();
  g_phase.store(Phase::stop, std::memory_order_release);
  second.join();

  // ---- report ----
  print_core_figures(timer, ticks);
  (void)std::printf("heap_guard_covers_malloc: %s\n", heap_guard_covers_malloc() ? "yes" : "no (sanitizer build)");
  (void)std::printf("heap_allocations_after_init: %" PRIu64 " allocations\n", heap.allocations);
  (void)std::printf("page_faults_after_init: %" PRIu64 " faults\n",
                    (faults_after.minor - faults_at_init.minor) + (faults_after.major - faults_at_init.major));
  return heap.allocations == 0 ? 0 : fail("bench", "heap allocation after init complete");
}

}  // namespace rescue::app
