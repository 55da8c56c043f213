#include "hal/time/clock.hpp"

#include <cerrno>
#include <ctime>

namespace rescue::hal {

Nanoseconds MonotonicClock::now() noexcept {
  timespec ts{};
  (void)clock_gettime(CLOCK_MONOTONIC, &ts);  // cannot fail for CLOCK_MONOTONIC with a valid pointer
  return static_cast<Nanoseconds>(ts.tv_sec) * kNsPerSec + ts.tv_nsec;
}

void MonotonicClock::sleep_until(Nanoseconds deadline) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline / kNsPerSec);
  ts.tv_nsec = static_cast<long>(deadline % kNsPerSec);
  // EINTR: a signal arrived; sleep on to the same absolute deadline.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace rescue::hal
