// LatencyHistogram: records durations (or any non-negative integer: ns, TSC ticks) into a fixed set
// of log-linear buckets, in place, without heap. Reports count, exact min and max, mean and standard
// deviation (from the exact integer sum and a double sum of squares: no division per record, so a
// real-time task can record every period cheaply) and percentiles p50/p90/p99/p99.9 to within one
// bucket. Two histograms merge (per-thread recording, one report).
//
// Buckets (the HdrHistogram layout): values 0..127 have one bucket each; above, every power-of-two
// range [2^e, 2^(e+1)) is split into 64 equal buckets, so a bucket is never wider than 1/64 (1.6 %)
// of the values in it. Values up to 2^40 - 1 (18 minutes in ns) are held; larger ones count in the
// last bucket and in saturated(). 2240 buckets of 8 bytes: about 18 KiB.
//
//   value:   0 1 2 ... 127 | 128 130 ... 254 | 256 260 ... 508 | 512 ...   (bucket lower bounds)
//   width:   1             | 2               | 4               | 8   ...
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>

namespace rescue {

struct HistogramSummary {
  std::uint64_t count{0};
  std::uint64_t min{0};
  std::uint64_t max{0};
  double mean{0.0};
  double stddev{0.0};  // population standard deviation
  std::uint64_t p50{0};
  std::uint64_t p90{0};
  std::uint64_t p99{0};
  std::uint64_t p999{0};
};

class LatencyHistogram {
 public:
  static constexpr unsigned kSubBucketBits = 7;
  static constexpr unsigned kMaxValueBits = 40;
  static constexpr std::size_t kExactBuckets = std::size_t{1} << kSubBucketBits;  // 128 buckets of width 1
  static constexpr std::size_t kBucketsPerOctave = kExactBuckets / 2;            // 64
  static constexpr std::size_t kBucketCount = kExactBuckets + (kMaxValueBits - kSubBucketBits) * kBucketsPerOctave;
  static constexpr std::uint64_t kMaxValue = (std::uint64_t{1} << kMaxValueBits) - 1;

  void record(std::uint64_t value) noexcept;
  // Adds every sample of `other`, as if recorded here.
  void merge(const LatencyHistogram& other) noexcept;
  void reset() noexcept { *this = LatencyHistogram{}; }

  std::uint64_t count() const noexcept { return count_; }
  std::uint64_t min() const noexcept { return count_ == 0 ? 0 : min_; }
  std::uint64_t max() const noexcept { return max_; }
  double mean() const noexcept { return count_ == 0 ? 0.0 : static_cast<double>(sum_) / static_cast<double>(count_); }
  double stddev() const noexcept;
  std::uint64_t saturated() const noexcept { return saturated_; }
  // Smallest bucket bound v such that at least `percent` % of the samples are <= v, clamped to
  // [min, max] (so percentile(0) == min and percentile(100) == max exactly). 0 when empty.
  std::uint64_t percentile(double percent) const noexcept;
  // Several percentiles in one pass over the buckets: `percents` ascending, out[i] as percentile(percents[i]).
  void percentiles(const double* percents, std::uint64_t* out, std::size_t n) const noexcept;
  HistogramSummary summary() const noexcept;

  // Bucket access, for plots: bucket i holds values lower(i)..upper(i) inclusive.
  static std::size_t bucket_of(std::uint64_t value) noexcept;
  static std::uint64_t bucket_lower(std::size_t bucket) noexcept;
  static std::uint64_t bucket_upper(std::size_t bucket) noexcept;
  std::uint64_t count_in(std::size_t bucket) const noexcept { return buckets_[bucket]; }

  // One `key: value unit` line per figure, keys prefixed with `name_` (e.g. "cycle_p99: 1043 ns").
  // stdio may allocate its buffer on the first write to a stream: print before init completes once,
  // or only from non-real-time code.
  void print(std::FILE* out, const char* name, const char* unit) const noexcept;

 private:
  std::array<std::uint64_t, kBucketCount> buckets_{};
  std::uint64_t count_{0};
  std::uint64_t min_{UINT64_MAX};
  std::uint64_t max_{0};
  std::uint64_t saturated_{0};
  std::uint64_t sum_{0};  // of the recorded values (clamped to kMaxValue: 2^24 samples of the largest fit)
  double sum_squares_{0.0};
};

}  // namespace rescue
