// Calendar time (Unix epoch) for records people read later, such as when a joint was lost. It is
// separate from hal::Clock because calendar time may jump (NTP, an operator setting the date): it
// stamps records and never schedules or measures anything.
#pragma once

#include <cstdint>

namespace rescue::hal {

class WallClock {
 public:
  WallClock() = default;
  WallClock(const WallClock&) = delete;
  WallClock& operator=(const WallClock&) = delete;
  WallClock(WallClock&&) = delete;
  WallClock& operator=(WallClock&&) = delete;
  virtual ~WallClock() = default;
  // Nanoseconds since 1970-01-01T00:00:00Z.
  virtual std::int64_t unix_time_ns() noexcept = 0;
};

// CLOCK_REALTIME.
class SystemWallClock final : public WallClock {
 public:
  std::int64_t unix_time_ns() noexcept override;
};

// A wall clock set by hand: tests and the simulator.
class ManualWallClock final : public WallClock {
 public:
  explicit ManualWallClock(std::int64_t unix_ns = 0) noexcept : now_(unix_ns) {}
  std::int64_t unix_time_ns() noexcept override { return now_; }
  void set(std::int64_t unix_ns) noexcept { now_ = unix_ns; }

 private:
  std::int64_t now_;
};

}  // namespace rescue::hal
