// The heap guard in strict mode while the core's real-time building blocks run: containers, the
// SPSC queue between two threads, the seqlock, the histogram, the TSC timer, errors as values.
// Any allocation would abort the test; afterwards the counters must read zero.
#include <gtest/gtest.h>

#include <cstdio>
#include <thread>

#include "core/containers/fixed_vector.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/timing/latency_histogram.hpp"
#include "core/base/result.hpp"
#include "core/containers/ring_buffer.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/concurrency/spsc_queue.hpp"
#include "hal/time/clock.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue {
namespace {

struct Sample {
  std::uint64_t sequence;
  std::int64_t value;
};

Result<int> checked_half(int value) {
  if (value % 2 != 0) return make_error(Errc::invalid_argument, "odd", static_cast<std::uint32_t>(value));
  return value / 2;
}

TEST(HeapGuard, StrictModeStaysSilentOnHeapFreeCode) {
  // Everything that may allocate happens before init complete: objects, the thread, the timer.
  static SpscQueue<Sample, 32> queue;
  static Seqlock<Sample> snapshot;
  static LatencyHistogram histogram;
  FixedVector<Sample, 16> vector;
  RingBuffer<Sample, 8> ring;
  hal::MonotonicClock clock;
  const hal::TscTimer timer = hal::TscTimer::calibrate(hal::kNsPerMs);
  std::uint64_t consumed = 0;
  char text[64];

  reopen_init_for_testing();
  std::thread consumer([&] {
    while (consumed < 10'000) {
      Sample s{};
      if (queue.try_pop(s)) {
        ++consumed;
        snapshot.write(s);
      } else {
        std::this_thread::yield();
      }
    }
  });
  declare_init_complete(HeapGuardMode::strict);

  int errors = 0;
  for (std::uint64_t i = 0; i < 10'000; ++i) {
    const std::uint64_t start = timer.start();
    const Sample s{i, static_cast<std::int64_t>(i) * 3};
    while (!queue.try_push(s)) std::this_thread::yield();
    if (!vector.push_back(s)) vector.clear();
    (void)ring.push_overwrite(s);
    Sample latest{};
    (void)snapshot.try_read(latest);
    if (!checked_half(static_cast<int>(i)).ok()) ++errors;
    (void)std::snprintf(text, sizeof text, "sample %llu", static_cast<unsigned long long>(i));
    (void)clock.now();
    histogram.record(static_cast<std::uint64_t>(timer.to_ns(timer.stop() - start)));
  }
  const HistogramSummary summary = histogram.summary();
  const HeapGuardCounters during = heap_guard_counters();
  reopen_init_for_testing();  // joining may free the thread's state: not part of the claim
  consumer.join();

  EXPECT_EQ(during.allocations, 0u);
  EXPECT_EQ(during.bytes, 0u);
  EXPECT_EQ(consumed, 10'000u);
  EXPECT_EQ(errors, 5'000);
  EXPECT_EQ(summary.count, 10'000u);
}

}  // namespace
}  // namespace rescue
