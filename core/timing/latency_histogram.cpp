#include "core/timing/latency_histogram.hpp"

#include <cinttypes>
#include <cmath>

namespace rescue {
namespace {

// Index of the highest set bit (value > 0).
unsigned log2_floor(std::uint64_t value) noexcept { return 63U - static_cast<unsigned>(__builtin_clzll(value)); }

}  // namespace

std::size_t LatencyHistogram::bucket_of(std::uint64_t value) noexcept {
  if (value > kMaxValue) value = kMaxValue;
  if (value < kExactBuckets) return static_cast<std::size_t>(value);
  const unsigned exponent = log2_floor(value);  // >= kSubBucketBits
  const unsigned shift = exponent - (kSubBucketBits - 1);
  const auto sub = static_cast<std::size_t>(value >> shift);  // in [64, 128)
  return kExactBuckets + (exponent - kSubBucketBits) * kBucketsPerOctave + (sub - kBucketsPerOctave);
}

std::uint64_t LatencyHistogram::bucket_lower(std::size_t bucket) noexcept {
  if (bucket < kExactBuckets) return bucket;
  const std::size_t k = bucket - kExactBuckets;
  const auto shift = static_cast<unsigned>(k / kBucketsPerOctave + 1);
  const std::uint64_t sub = kBucketsPerOctave + k % kBucketsPerOctave;
  return sub << shift;
}

std::uint64_t LatencyHistogram::bucket_upper(std::size_t bucket) noexcept {
  if (bucket < kExactBuckets) return bucket;
  const std::size_t k = bucket - kExactBuckets;
  const auto shift = static_cast<unsigned>(k / kBucketsPerOctave + 1);
  const std::uint64_t sub = kBucketsPerOctave + k % kBucketsPerOctave;
  return ((sub + 1) << shift) - 1;
}

void LatencyHistogram::record(std::uint64_t value) noexcept {
  if (value > kMaxValue) ++saturated_;
  ++buckets_[bucket_of(value)];
  ++count_;
  if (value < min_) min_ = value;
  if (value > max_) max_ = value;
  const std::uint64_t clamped = value > kMaxValue ? kMaxValue : value;
  sum_ += clamped;
  const auto x = static_cast<double>(clamped);
  sum_squares_ += x * x;
}

void LatencyHistogram::merge(const LatencyHistogram& other) noexcept {
  if (other.count_ == 0) return;
  for (std::size_t i = 0; i < kBucketCount; ++i) buckets_[i] += other.buckets_[i];
  sum_ += other.sum_;
  sum_squares_ += other.sum_squares_;
  count_ += other.count_;
  saturated_ += other.saturated_;
  if (other.min_ < min_) min_ = other.min_;
  if (other.max_ > max_) max_ = other.max_;
}

double LatencyHistogram::stddev() const noexcept {
  if (count_ == 0) return 0.0;
  const double mean_value = mean();
  const double variance = sum_squares_ / static_cast<double>(count_) - mean_value * mean_value;
  return variance > 0.0 ? std::sqrt(variance) : 0.0;  // rounding may leave a tiny negative
}

std::uint64_t LatencyHistogram::percentile(double percent) const noexcept {
  if (count_ == 0) return 0;
  if (!(percent > 0.0)) return min_;  // also NaN
  if (percent >= 100.0) return max_;
  // Rank of the sample that `percent` % of the samples do not exceed (1-based, nearest-rank).
  auto rank = static_cast<std::uint64_t>(std::ceil(percent / 100.0 * static_cast<double>(count_)));
  if (rank == 0) rank = 1;
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < kBucketCount; ++i) {
    seen += buckets_[i];
    if (seen >= rank) {
      const std::uint64_t upper = bucket_upper(i);
      if (upper < min_) return min_;
      return upper > max_ ? max_ : upper;
    }
  }
  return max_;
}

void LatencyHistogram::percentiles(const double* percents, std::uint64_t* out, std::size_t n) const noexcept {
  std::size_t k = 0;
  // The ends, as percentile() answers them.
  while (k < n && (count_ == 0 || !(percents[k] > 0.0) || percents[k] >= 100.0)) {
    out[k] = count_ == 0 ? 0 : (percents[k] >= 100.0 ? max_ : min_);
    ++k;
  }
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < kBucketCount && k < n; ++i) {
    seen += buckets_[i];
    while (k < n) {
      if (percents[k] >= 100.0) {
        out[k++] = max_;
        continue;
      }
      auto rank = static_cast<std::uint64_t>(std::ceil(percents[k] / 100.0 * static_cast<double>(count_)));
      if (rank == 0) rank = 1;
      if (seen < rank) break;
      const std::uint64_t upper = bucket_upper(i);
      out[k++] = upper < min_ ? min_ : (upper > max_ ? max_ : upper);
    }
  }
  for (; k < n; ++k) out[k] = max_;
}

HistogramSummary LatencyHistogram::summary() const noexcept {
  HistogramSummary s;
  s.count = count_;
  s.min = min();
  s.max = max_;
  s.mean = mean();
  s.stddev = stddev();
  s.p50 = percentile(50.0);
  s.p90 = percentile(90.0);
  s.p99 = percentile(99.0);
  s.p999 = percentile(99.9);
  return s;
}

void LatencyHistogram::print(std::FILE* out, const char* name, const char* unit) const noexcept {
  const HistogramSummary s = summary();
  std::fprintf(out, "%s_count: %" PRIu64 " samples\n", name, s.count);
  std::fprintf(out, "%s_min: %" PRIu64 " %s\n", name, s.min, unit);
  std::fprintf(out, "%s_mean: %.1f %s\n", name, s.mean, unit);
  std::fprintf(out, "%s_std: %.1f %s\n", name, s.stddev, unit);
  std::fprintf(out, "%s_max: %" PRIu64 " %s\n", name, s.max, unit);
  std::fprintf(out, "%s_p50: %" PRIu64 " %s\n", name, s.p50, unit);
  std::fprintf(out, "%s_p90: %" PRIu64 " %s\n", name, s.p90, unit);
  std::fprintf(out, "%s_p99: %" PRIu64 " %s\n", name, s.p99, unit);
  std::fprintf(out, "%s_p99.9: %" PRIu64 " %s\n", name, s.p999, unit);
  std::fprintf(out, "%s_saturated: %" PRIu64 " samples\n", name, saturated_);
}

}  // namespace rescue
