// A heartbeat read from the shared segment (TaskLinks::rc_heartbeat_ns, task_heartbeat_ns: the
// writer's monotonic time at the end of its latest period, 0 before its first), judged against the
// reader's clock before its age is used. The writer only writes times of its clock, so a negative
// value, or one further ahead of the reader's clock than kHeartbeatAheadLimitNs, is damage (a stray
// write, a bit flip): its age is not computed (`now - beat` could overflow, and a time from the
// future would read as a task that beat just now for as long as it lies ahead). A beat at most that
// far ahead is taken as now: the writer beat after the reader read its clock (a reader preempted on a
// loaded host), so a silence is hidden at most that long. Readers of a damaged beat go by whether it
// moves (docs/shared-memory.md "Records: what each reader checks").
#pragma once

#include <cstdint>

#include "hal/time/clock.hpp"

namespace rescue::app {

constexpr hal::Nanoseconds kHeartbeatAheadLimitNs = 1'000'000'000;

struct HeartbeatAge {
  enum class Kind : std::uint8_t { never, whole, damaged };
  Kind kind{Kind::never};
  hal::Nanoseconds age{0};  // whole: how old the beat is at `now` (0 for one ahead within the limit)
};

// `now`: the reader's monotonic clock (never negative).
constexpr HeartbeatAge heartbeat_age(hal::Nanoseconds now, std::int64_t beat) noexcept {
  if (beat == 0) return HeartbeatAge{HeartbeatAge::Kind::never, 0};
  if (beat < 0 || now < 0) return HeartbeatAge{HeartbeatAge::Kind::damaged, 0};
  if (beat > now) {
    if (beat - now > kHeartbeatAheadLimitNs) return HeartbeatAge{HeartbeatAge::Kind::damaged, 0};
    return HeartbeatAge{HeartbeatAge::Kind::whole, 0};
  }
  return HeartbeatAge{HeartbeatAge::Kind::whole, now - beat};
}

}  // namespace rescue::app
