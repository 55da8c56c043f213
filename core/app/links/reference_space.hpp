// One RC task's reference space (design brief section 3): the joint references it computed this
// period, written by that task alone and read by the EtherCAT handler, through a seqlock
// (core/concurrency/seqlock.hpp: its protocol and memory ordering):
//   writer  begin(): the seqlock's write begun (readers get nothing); set() each joint into the
//           writer's draft; complete(): the period's facts, the draft written as one snapshot
//   reader  read(): the latest complete period, else false (never written, or being written)
// A writer that dies between begin() and complete() leaves the write begun: readers get false
// until the restarted writer completes a period; they never see half a period.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "core/concurrency/seqlock.hpp"
#include "core/robot/robot.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

// What a reader copies out of a reference space. Trivial (published through a seqlock):
// value-initialise it.
struct ReferenceSnapshot {
  std::uint64_t owner_word;       // the Motion owner word its writer held (0: it did not own the motion)
  std::uint64_t period;           // the writer's period count
  hal::Nanoseconds completed_ns;  // when the writer completed it (the tasks' common monotonic clock)
  JointMask commanded;            // the joints these references command
  std::array<double, kJointCount> position_rad;  // positions only: the joints run in CSP (no velocity reference)
};
static_assert(std::is_trivial_v<ReferenceSnapshot>, "published through a seqlock");

class ReferenceSpace {
 public:
  static constexpr std::uint32_t kReadAttempts = 4;

  ReferenceSpace() noexcept {
    static_assert(std::is_standard_layout_v<ReferenceSpace>, "shared between processes: standard layout only");
    static_assert(std::is_trivially_destructible_v<ReferenceSpace>, "unmapped without being destroyed");
  }
  ReferenceSpace(const ReferenceSpace&) = delete;
  ReferenceSpace& operator=(const ReferenceSpace&) = delete;
  ReferenceSpace(ReferenceSpace&&) = delete;
  ReferenceSpace& operator=(ReferenceSpace&&) = delete;
  ~ReferenceSpace() = default;

  // ---- the writer (its RC task only) ----
  void begin() noexcept { published_.begin_write(); }
  void set(std::size_t joint, double position_rad) noexcept { draft_.position_rad[joint] = position_rad; }
  void complete(std::uint64_t owner_word, std::uint64_t period, JointMask commanded, hal::Nanoseconds now) noexcept {
    draft_.owner_word = owner_word;
    draft_.period = period;
    draft_.commanded = commanded;
    draft_.completed_ns = now;
    published_.write(draft_);
  }

  // ---- readers ----
  // The latest complete period's references; false when none is complete (never written, being
  // written in every attempt, or left incomplete by a writer that died).
  [[nodiscard]] bool read(ReferenceSnapshot& out) const noexcept {
    return completed() != 0 && published_.try_read(out, kReadAttempts);
  }
  // Completed periods so far (0: never).
  std::uint64_t completed() const noexcept { return published_.version(); }

 private:
  Seqlock<ReferenceSnapshot> published_;
  ReferenceSnapshot draft_{};  // the writer's own: the period being written (readers never touch it)
};

}  // namespace rescue::app
