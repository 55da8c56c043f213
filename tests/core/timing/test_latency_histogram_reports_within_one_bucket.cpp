#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/timing/latency_histogram.hpp"

namespace rescue {
namespace {

using H = LatencyHistogram;

TEST(LatencyHistogram, BucketsTileTheRangeWithoutGaps) {
  EXPECT_EQ(H::bucket_lower(0), 0u);
  for (std::size_t i = 0; i + 1 < H::kBucketCount; ++i) {
    ASSERT_LE(H::bucket_lower(i), H::bucket_upper(i)) << i;
    ASSERT_EQ(H::bucket_upper(i) + 1, H::bucket_lower(i + 1)) << i;
  }
  EXPECT_EQ(H::bucket_upper(H::kBucketCount - 1), H::kMaxValue);
}

TEST(LatencyHistogram, EveryValueFallsInABucketAtMostOneSixtyFourthWide) {
  for (std::uint64_t v = 0; v < 5'000'000; v = v < 1000 ? v + 1 : v + v / 97 + 1) {
    const std::size_t b = H::bucket_of(v);
    ASSERT_LE(H::bucket_lower(b), v);
    ASSERT_GE(H::bucket_upper(b), v);
    const std::uint64_t width = H::bucket_upper(b) - H::bucket_lower(b) + 1;
    ASSERT_LE(width, H::bucket_lower(b) / 64 + 1) << v;
  }
}

TEST(LatencyHistogram, ExactStatisticsAndPercentilesOfAUniformSet) {
  H h;
  for (std::uint64_t v = 1; v <= 10'000; ++v) h.record(v);
  const HistogramSummary s = h.summary();
  EXPECT_EQ(s.count, 10'000u);
  EXPECT_EQ(s.min, 1u);
  EXPECT_EQ(s.max, 10'000u);
  EXPECT_NEAR(s.mean, 5000.5, 1e-9);
  EXPECT_NEAR(s.stddev, std::sqrt((10'000.0 * 10'000.0 - 1.0) / 12.0), 1e-6);
  // Percentiles are bucket upper bounds: never below the true value, at most one bucket above.
  auto within_a_bucket = [](std::uint64_t reported, std::uint64_t truth) {
    return reported >= truth && reported <= truth + truth / 64 + 1;
  };
  EXPECT_TRUE(within_a_bucket(s.p50, 5'000)) << s.p50;
  EXPECT_TRUE(within_a_bucket(s.p90, 9'000)) << s.p90;
  EXPECT_TRUE(within_a_bucket(s.p99, 9'900)) << s.p99;
  EXPECT_TRUE(within_a_bucket(s.p999, 9'990)) << s.p999;
  EXPECT_EQ(h.percentile(0.0), 1u);
  EXPECT_EQ(h.percentile(100.0), 10'000u);
}

TEST(LatencyHistogram, SmallValuesAreExact) {
  H h;
  for (int i = 0; i < 99; ++i) h.record(20);
  h.record(100);
  EXPECT_EQ(h.percentile(50.0), 20u);
  EXPECT_EQ(h.percentile(99.0), 20u);
  EXPECT_EQ(h.percentile(99.9), 100u);
}

TEST(LatencyHistogram, MergeEqualsRecordingEverythingInOne) {
  H odd;
  H even;
  H all;
  for (std::uint64_t v = 0; v < 20'000; ++v) {
    const std::uint64_t x = (v * 7919) % 1'000'003 + 1000;  // spread over several octaves
    (v % 2 == 0 ? even : odd).record(x);
    all.record(x);
  }
  H merged = odd;
  merged.merge(even);
  const HistogramSummary m = merged.summary();
  const HistogramSummary a = all.summary();
  EXPECT_EQ(m.count, a.count);
  EXPECT_EQ(m.min, a.min);
  EXPECT_EQ(m.max, a.max);
  EXPECT_NEAR(m.mean, a.mean, a.mean * 1e-12);
  EXPECT_NEAR(m.stddev, a.stddev, a.stddev * 1e-9);
  EXPECT_EQ(m.p50, a.p50);
  EXPECT_EQ(m.p999, a.p999);
  for (std::size_t i = 0; i < H::kBucketCount; ++i) ASSERT_EQ(merged.count_in(i), all.count_in(i)) << i;
}

TEST(LatencyHistogram, MergingAnEmptyHistogramChangesNothing) {
  H h;
  h.record(5);
  h.merge(H{});
  EXPECT_EQ(h.count(), 1u);
  H empty;
  empty.merge(h);
  EXPECT_EQ(empty.min(), 5u);
  EXPECT_EQ(empty.max(), 5u);
}

TEST(LatencyHistogram, HugeValuesSaturateButKeepTheExactMax) {
  H h;
  h.record(H::kMaxValue + 12345);
  EXPECT_EQ(h.saturated(), 1u);
  EXPECT_EQ(h.max(), H::kMaxValue + 12345);
  EXPECT_EQ(h.count_in(H::kBucketCount - 1), 1u);
}

TEST(LatencyHistogram, EmptyReportsZeros) {
  const HistogramSummary s = H{}.summary();
  EXPECT_EQ(s.count, 0u);
  EXPECT_EQ(s.min, 0u);
  EXPECT_EQ(s.p99, 0u);
  EXPECT_EQ(s.stddev, 0.0);
}

// "cycle_<key>: <number> <unit>" with a decimal number and unit ns or samples.
bool is_key_value_unit(const std::string& line) {
  const std::size_t colon = line.find(": ");
  const std::size_t space = line.rfind(' ');
  if (line.rfind("cycle_", 0) != 0 || colon == std::string::npos || space <= colon + 2) return false;
  const std::string number = line.substr(colon + 2, space - colon - 2);
  const std::string unit = line.substr(space + 1);
  if (number.find_first_not_of("0123456789.") != std::string::npos || number.empty()) return false;
  if (line.substr(0, colon).find(' ') != std::string::npos) return false;
  return unit == "ns" || unit == "samples";
}

TEST(LatencyHistogram, PrintsOneKeyValueUnitLinePerFigure) {
  H h;
  for (std::uint64_t v = 900; v < 1100; ++v) h.record(v);
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  ASSERT_NE(out, nullptr);
  h.print(out, "cycle", "ns");
  std::fclose(out);
  const std::string printed(text, size);
  std::free(text);
  int lines = 0;
  std::size_t start = 0;
  for (std::size_t end = printed.find('\n'); end != std::string::npos; end = printed.find('\n', start)) {
    const std::string one = printed.substr(start, end - start);
    EXPECT_TRUE(is_key_value_unit(one)) << one;
    ++lines;
    start = end + 1;
  }
  EXPECT_EQ(lines, 10);
  EXPECT_NE(printed.find("cycle_min: 900 ns\n"), std::string::npos) << printed;
  EXPECT_NE(printed.find("cycle_max: 1099 ns\n"), std::string::npos) << printed;
  EXPECT_NE(printed.find("cycle_p99.9: "), std::string::npos) << printed;
}

}  // namespace
}  // namespace rescue
