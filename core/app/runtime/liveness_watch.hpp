// The supervisor's liveness watch (docs/tasks.md "Liveness"): each task stores its heartbeat (the
// monotonic time at the end of its latest period) in its slot of TaskLinks::task_heartbeat_ns; the
// supervisor (or, under --threads, the logging thread) checks the watched tasks' heartbeats on
// every pass and reports a task that has completed no period for `silent_after` (once, when it goes
// silent) and again when it completes a period again (how long it was silent). The decision is a
// pure function of the heartbeats and the time, so it is tested on virtual time. No heap.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "core/app/links/heartbeat.hpp"
#include "core/app/links/task_links.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

struct LivenessChange {
  enum class Kind : std::uint8_t { none, silent, resumed };
  Kind kind{Kind::none};
  std::size_t task{0};             // StatTask slot
  hal::Nanoseconds silent_ns{0};   // silent: the heartbeat's age now; resumed: how long it was silent
};

class LivenessWatch {
 public:
  using Heartbeats = std::array<std::atomic<std::int64_t>, kHeartbeatSlots>;

  // Watches the StatTask slots in `watched` (bit k = slot k).
  LivenessWatch(hal::Nanoseconds silent_after, std::uint32_t watched) noexcept
      : silent_after_(silent_after), watched_(watched) {}

  // One check at `now`; writes the changes since the last check into `out` (at most one per task);
  // returns how many. A task that has not beaten yet (0: before its first period) is not watched.
  // A beat is also judged by whether it moves: one that has not changed for `silent_after` on this
  // clock is silent whatever its value, so a damaged beat (heartbeat.hpp: negative, or from the
  // future) neither hides a silent task nor makes a running one (it rewrites its beat every period)
  // look silent; each damaged value seen is counted.
  std::size_t check(hal::Nanoseconds now, const Heartbeats& beats, std::array<LivenessChange, kTaskStatSlots>& out) noexcept {
    std::size_t n = 0;
    for (std::size_t k = 0; k < kTaskStatSlots; ++k) {
      if ((watched_ & (1U << k)) == 0) continue;
      const std::int64_t beat = beats[k].load(std::memory_order_acquire);
      const HeartbeatAge judged = heartbeat_age(now, beat);
      if (judged.kind == HeartbeatAge::Kind::never && !seen_[k]) continue;
      if (!seen_[k] || beat != last_beat_[k]) {
        seen_[k] = true;
        last_beat_[k] = beat;
        moved_at_[k] = now;
        if (judged.kind != HeartbeatAge::Kind::whole) ++damaged_;  // a 0 after a beat is damage too
      }
      const hal::Nanoseconds unmoved = now - moved_at_[k];
      const hal::Nanoseconds age = judged.kind == HeartbeatAge::Kind::whole ? std::max(judged.age, unmoved) : unmoved;
      if (!silent_[k] && age > silent_after_) {
        silent_[k] = true;
        silent_since_[k] = beat;
        silent_from_[k] = now - age;
        ++reports_;
        out[n++] = LivenessChange{LivenessChange::Kind::silent, k, age};
      } else if (silent_[k] && beat != silent_since_[k]) {
        silent_[k] = false;
        // How long it was silent: from its last beat to this one, on the beats' own clock when
        // both are whole, else on this clock.
        const bool whole = judged.kind == HeartbeatAge::Kind::whole &&
                           heartbeat_age(now, silent_since_[k]).kind == HeartbeatAge::Kind::whole && beat > silent_since_[k];
        out[n++] = LivenessChange{LivenessChange::Kind::resumed, k, whole ? beat - silent_since_[k] : now - silent_from_[k]};
      }
    }
    return n;
  }

  bool silent(std::size_t task) const noexcept { return silent_[task]; }
  // Silences reported so far.
  std::uint64_t reports() const noexcept { return reports_; }
  // Damaged heartbeat values seen (heartbeat.hpp), each distinct value once.
  std::uint64_t damaged_beats() const noexcept { return damaged_; }
  hal::Nanoseconds silent_after() const noexcept { return silent_after_; }

 private:
  hal::Nanoseconds silent_after_;
  std::uint32_t watched_;
  std::array<bool, kTaskStatSlots> silent_{};
  std::array<std::int64_t, kTaskStatSlots> silent_since_{};
  std::array<hal::Nanoseconds, kTaskStatSlots> silent_from_{};  // this clock's time of the silence's start
  std::array<bool, kTaskStatSlots> seen_{};                     // a beat was seen
  std::array<std::int64_t, kTaskStatSlots> last_beat_{};
  std::array<hal::Nanoseconds, kTaskStatSlots> moved_at_{};     // this clock's time the beat last changed
  std::uint64_t reports_{0};
  std::uint64_t damaged_{0};
};

}  // namespace rescue::app
