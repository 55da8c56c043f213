// Rate limit of a log line that repeats (issue 36 item 11: 1 502 liveness lines in a 10-minute run on
// a loaded host): per key (a task), the first line is printed, then at most one per `interval`; the
// lines in between are counted, and the next printed line says how many were left out. A pure
// function of the time passed in, so it is tested on virtual time. No heap.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "hal/time/clock.hpp"

namespace rescue::app {

template <std::size_t Keys>
class RepeatLimiter {
 public:
  struct Decision {
    bool print{false};
    bool first{false};             // the key's first line: print it whole (its explanation too)
    std::uint64_t suppressed{0};   // lines of this key left out since its last printed line
  };

  explicit RepeatLimiter(hal::Nanoseconds interval) noexcept : interval_(interval) {}

  // One occurrence of `key` at `now`: print it, or count it as suppressed.
  Decision admit(std::size_t key, hal::Nanoseconds now) noexcept {
    Slot& s = slots_[key];
    if (s.printed && now - s.printed_at < interval_) {
      ++s.suppressed;
      ++suppressed_total_;
      return Decision{};
    }
    const Decision d{true, !s.printed, s.suppressed};
    s.printed = true;
    s.printed_at = now;
    s.suppressed = 0;
    return d;
  }

  // Lines of `key` left out and not yet mentioned by a printed line.
  std::uint64_t pending(std::size_t key) const noexcept { return slots_[key].suppressed; }
  // Every line left out so far, all keys.
  std::uint64_t suppressed_total() const noexcept { return suppressed_total_; }
  hal::Nanoseconds interval() const noexcept { return interval_; }

 private:
  struct Slot {
    bool printed{false};
    hal::Nanoseconds printed_at{0};
    std::uint64_t suppressed{0};
  };
  hal::Nanoseconds interval_;
  std::array<Slot, Keys> slots_{};
  std::uint64_t suppressed_total_{0};
};

}  // namespace rescue::app
