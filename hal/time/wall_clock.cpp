#include "hal/time/wall_clock.hpp"

#include <ctime>

namespace rescue::hal {

std::int64_t SystemWallClock::unix_time_ns() noexcept {
  timespec ts{};
  if (::clock_gettime(CLOCK_REALTIME, &ts) != 0) return 0;
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000LL + ts.tv_nsec;
}

}  // namespace rescue::hal
