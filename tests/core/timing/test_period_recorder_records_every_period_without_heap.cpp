// PeriodRecorder: every period lands in both histograms with its execution time (ticks scaled to ns)
// and wake-up latency; recording allocates nothing (heap guard strict: any allocation aborts); the
// CSV and the cyclictest-style histogram carry the figures.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "core/memory/heap_guard.hpp"
#include "core/timing/period_recorder.hpp"

namespace rescue {
namespace {

std::string read_all(std::FILE* f) {
  std::rewind(f);
  std::string text;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) text.append(buffer, n);
  return text;
}

TEST(PeriodRecorder, RecordsEveryPeriodWithoutHeap) {
  static PeriodRecorder recorder;
  recorder.configure("ethercat", 0.5);  // 2 ticks per ns
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);
  for (std::uint64_t i = 0; i < 10'000; ++i) {
    // execution 2000 + (i % 100) ticks = 1000..1049 ns; latency 3000 ns, two late periods of 120 us.
    recorder.record(i == 5000 || i == 6000 ? 120'000 : 3000, 1'000'000 * i, 1'000'000 * i + 2000 + (i % 100));
  }
  recorder.record(-5, 10, 20);  // a clock step backwards counts as 0 latency, never underflows
  const HeapGuardCounters heap = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(heap.allocations, 0U);

  EXPECT_EQ(recorder.periods(), 10'001U);
  EXPECT_EQ(recorder.execution().min(), 5U);
  EXPECT_EQ(recorder.execution().max(), 1049U);
  EXPECT_EQ(recorder.latency().min(), 0U);
  EXPECT_EQ(recorder.latency().max(), 120'000U);
  const PeriodFigures f = PeriodRecorder::figures(recorder.latency());
  EXPECT_GE(f.summary.p99, 3000U);  // within one bucket (1/64) above
  EXPECT_LE(f.summary.p99, 3000U + 3000U / 64U);
  EXPECT_EQ(f.p9999, 120'000U);  // 2 in 10 001 samples: p99.99 reaches them (clamped to max)
}

TEST(PeriodRecorder, WritesCsvAndCyclictestHistogram) {
  static PeriodRecorder a;
  static PeriodRecorder b;
  a.configure("ethercat", 1.0);
  b.configure("joint_manager", 1.0);
  for (int i = 0; i < 100; ++i) a.record(2500, 0, 800);
  b.record(70'500, 0, 100);
  const PeriodRecorder* both[] = {&a, &b};

  std::FILE* csv = std::tmpfile();
  ASSERT_NE(csv, nullptr);
  ASSERT_TRUE(PeriodRecorder::write_csv(csv, Span<const PeriodRecorder* const>(both)));
  const std::string text = read_all(csv);
  std::fclose(csv);
  EXPECT_NE(text.find("task,figure,unit,count,min,mean,std,max,p50,p99,p99.9,p99.99\n"), std::string::npos);
  EXPECT_NE(text.find("ethercat,execution,ns,100,800,800.0,0.0,800,800,800,800,800\n"), std::string::npos);
  EXPECT_NE(text.find("ethercat,wakeup_latency,ns,100,2500,"), std::string::npos);
  EXPECT_NE(text.find("joint_manager,wakeup_latency,ns,1,70500,"), std::string::npos);

  std::FILE* hist = std::tmpfile();
  ASSERT_NE(hist, nullptr);
  ASSERT_TRUE(PeriodRecorder::write_cyclictest_histogram(hist, Span<const PeriodRecorder* const>(both), 100));
  const std::string h = read_all(hist);
  std::fclose(hist);
  EXPECT_NE(h.find("\n000002 000100 000000\n"), std::string::npos);  // 2.5 us: microsecond 2
  // 70.5 us: its bucket (1024 ns wide above 65.5 us) starts at 69.6 us: counted in microsecond 69.
  EXPECT_NE(h.find("\n000069 000000 000001\n"), std::string::npos);
  EXPECT_NE(h.find("# Total: 000100 000001\n"), std::string::npos);
  EXPECT_NE(h.find("# Max Latencies: 000002 000070\n"), std::string::npos);
  EXPECT_NE(h.find("# Histogram Overflows: 000000 000000\n"), std::string::npos);
}

}  // namespace
}  // namespace rescue
