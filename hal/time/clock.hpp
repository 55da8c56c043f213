// Time comes from a Clock, never from the OS directly, so every task and test can run on
// virtual time: deterministic and faster than real time. Times are signed nanoseconds on a
// monotonic time base whose zero is arbitrary (CLOCK_MONOTONIC for the real clock).
#pragma once

#include <cstdint>

namespace rescue::hal {

using Nanoseconds = std::int64_t;

constexpr Nanoseconds kNsPerUs = 1'000;
constexpr Nanoseconds kNsPerMs = 1'000'000;
constexpr Nanoseconds kNsPerSec = 1'000'000'000;

// A duration in seconds, for reports and logs (the one conversion of the program).
constexpr double seconds(Nanoseconds ns) noexcept { return static_cast<double>(ns) / static_cast<double>(kNsPerSec); }

class Clock {
 public:
  Clock() = default;
  Clock(const Clock&) = delete;
  Clock& operator=(const Clock&) = delete;
  Clock(Clock&&) = delete;
  Clock& operator=(Clock&&) = delete;
  virtual ~Clock() = default;

  // Current time; never goes backwards.
  virtual Nanoseconds now() noexcept = 0;
  // Blocks until now() >= deadline (returns at once if already past).
  virtual void sleep_until(Nanoseconds deadline) noexcept = 0;
};

// CLOCK_MONOTONIC with absolute-deadline clock_nanosleep (no drift from relative sleeps).
class MonotonicClock final : public Clock {
 public:
  Nanoseconds now() noexcept override;
  void sleep_until(Nanoseconds deadline) noexcept override;
};

// Virtual time for tests and the simulator: time moves only when someone advances it or sleeps.
// Not thread-safe: one thread drives virtual time.
class VirtualClock final : public Clock {
 public:
  explicit VirtualClock(Nanoseconds start = 0) noexcept : now_(start) {}
  Nanoseconds now() noexcept override { return now_; }
  void sleep_until(Nanoseconds deadline) noexcept override {
    if (deadline > now_) now_ = deadline;
  }
  void advance(Nanoseconds delta) noexcept {
    if (delta > 0) now_ += delta;
  }

 private:
  Nanoseconds now_;
};

}  // namespace rescue::hal
