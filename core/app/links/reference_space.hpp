// One RC task's reference space (design brief section 3): the joint references it computed this
// period, written by that task alone (single writer, no lock) and read by the EtherCAT handler.
// A period's references are marked complete by the sequence number, seqlock-style
// (core/concurrency/seqlock.hpp explains the memory ordering; every word is an atomic, so readers
// race with nothing):
//   writer  begin(): sequence odd; set() each joint; complete(): the period's facts, sequence even
//   reader  read(): sequence even and unchanged across the copy, else false (incomplete or torn)
// A writer that dies between begin() and complete() leaves the sequence odd: readers get false
// until the restarted writer completes a period; they never see half a period.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "core/robot/robot.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

// What a reader copies out of a reference space.
struct ReferenceSnapshot {
  std::uint64_t owner_word{0};       // the Motion owner word its writer held (0: it did not own the motion)
  std::uint64_t period{0};           // the writer's period count
  hal::Nanoseconds completed_ns{0};  // when the writer completed it (the tasks' common monotonic clock)
  JointMask commanded{0};            // the joints these references command
  std::array<double, kJointCount> position_rad{};
  std::array<double, kJointCount> velocity_rad_s{};
};

class ReferenceSpace {
 public:
  static constexpr std::uint32_t kReadAttempts = 4;

  ReferenceSpace() noexcept {
    static_assert(std::atomic<double>::is_always_lock_free, "shared between processes: lock-free only");
    static_assert(std::is_standard_layout_v<ReferenceSpace>, "shared between processes: standard layout only");
    static_assert(std::is_trivially_destructible_v<ReferenceSpace>, "unmapped without being destroyed");
  }
  ReferenceSpace(const ReferenceSpace&) = delete;
  ReferenceSpace& operator=(const ReferenceSpace&) = delete;
  ReferenceSpace(ReferenceSpace&&) = delete;
  ReferenceSpace& operator=(ReferenceSpace&&) = delete;
  ~ReferenceSpace() = default;

  // ---- the writer (its RC task only) ----
  void begin() noexcept {
    // `| 1` also resumes cleanly after a writer that died with the sequence odd.
    writing_ = sequence_.load(std::memory_order_relaxed) | 1U;
    sequence_.store(writing_, std::memory_order_relaxed);
  }
  void set(std::size_t joint, double position_rad, double velocity_rad_s) noexcept {
    position_[joint].store(position_rad, std::memory_order_release);
    velocity_[joint].store(velocity_rad_s, std::memory_order_release);
  }
  void complete(std::uint64_t owner_word, std::uint64_t period, JointMask commanded, hal::Nanoseconds now) noexcept {
    owner_word_.store(owner_word, std::memory_order_release);
    period_.store(period, std::memory_order_release);
    commanded_.store(commanded, std::memory_order_release);
    completed_ns_.store(now, std::memory_order_release);
    sequence_.store(writing_ + 1, std::memory_order_release);
  }

  // ---- readers ----
  // The latest complete period's references; false when none is complete (never written, being
  // written in every attempt, or left incomplete by a writer that died).
  [[nodiscard]] bool read(ReferenceSnapshot& out) const noexcept {
    ReferenceSnapshot copy;
    for (std::uint32_t attempt = 0; attempt < kReadAttempts; ++attempt) {
      const std::uint64_t before = sequence_.load(std::memory_order_acquire);
      if (before == 0 || (before & 1U) != 0) continue;
      copy.owner_word = owner_word_.load(std::memory_order_acquire);
      copy.period = period_.load(std::memory_order_acquire);
      copy.commanded = commanded_.load(std::memory_order_acquire);
      copy.completed_ns = completed_ns_.load(std::memory_order_acquire);
      for (std::size_t j = 0; j < kJointCount; ++j) {
        copy.position_rad[j] = position_[j].load(std::memory_order_acquire);
        copy.velocity_rad_s[j] = velocity_[j].load(std::memory_order_acquire);
      }
      if (sequence_.load(std::memory_order_relaxed) == before) {
        out = copy;
        return true;
      }
    }
    return false;
  }
  // Completed periods so far (0: never).
  std::uint64_t completed() const noexcept { return sequence_.load(std::memory_order_acquire) / 2; }

 private:
  std::atomic<std::uint64_t> sequence_{0};  // 0: never written; odd: a period being written; even: complete
  std::atomic<std::uint64_t> owner_word_{0};
  std::atomic<std::uint64_t> period_{0};
  std::atomic<JointMask> commanded_{0};
  std::atomic<std::int64_t> completed_ns_{0};
  std::array<std::atomic<double>, kJointCount> position_{};
  std::array<std::atomic<double>, kJointCount> velocity_{};
  std::uint64_t writing_{0};  // the writer's own: the odd value of the period being written
};

}  // namespace rescue::app
