// The Motion owner (design brief section 3, paper IV-A): which RC task's references drive the joints.
// One 64-bit atomic word, generation << 8 | task, so it lives in shared memory and no process can
// hold it locked: every change is one compare-exchange from the word the changer observed.
//   take(task)       the operator hands the motion to `task` (from whoever owns it, or nobody)
//   take_if_free     a task takes the motion only when nobody owns it
//   release(word)    the owner gives it up, or the EtherCAT handler frees the word of an owner whose
//                    heartbeat stopped: succeeds only if the word is still `word`, so a release can
//                    never undo a newer take
//   release_to_operator(word)  as release, but the free motion is held for the operator: no task
//                    takes it back by itself (take_if_free refuses) until the operator's take. The
//                    handler's release after the drives' watchdog expired (docs/tasks.md "Liveness").
// Every change increments the generation: references written under an older word are never used
// (the reference space carries the word its writer held, docs/motion-owner.md).
#pragma once

#include <atomic>
#include <cstdint>
#include <type_traits>

namespace rescue::app {

constexpr std::uint8_t kNoOwnerTask = 0xFF;  // protocol::kNoOwner on the wire

class MotionOwner {
 public:
  static constexpr std::uint64_t kNobody = kNoOwnerTask;  // generation 0, no task
  // Set only on a free word: nobody owns the motion and only the operator's take() gives it again.
  static constexpr std::uint64_t kHeldForOperator = std::uint64_t{1} << 63U;

  static constexpr std::uint8_t task_of(std::uint64_t word) noexcept { return static_cast<std::uint8_t>(word & 0xFFU); }
  static constexpr std::uint64_t generation_of(std::uint64_t word) noexcept { return (word & ~kHeldForOperator) >> 8U; }
  static constexpr bool held_for_operator(std::uint64_t word) noexcept { return (word & kHeldForOperator) != 0; }
  static constexpr std::uint64_t make(std::uint64_t generation, std::uint8_t task) noexcept {
    return (generation << 8U) | task;
  }

  MotionOwner() noexcept {
    static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "shared between processes: lock-free only");
    static_assert(std::is_standard_layout_v<MotionOwner>, "shared between processes: standard layout only");
  }

  std::uint64_t word() const noexcept { return word_.load(std::memory_order_acquire); }
  std::uint8_t task() const noexcept { return task_of(word()); }

  // The operator's handover: `task` owns the motion from now on; returns the new word.
  std::uint64_t take(std::uint8_t task) noexcept {
    std::uint64_t seen = word_.load(std::memory_order_acquire);
    for (;;) {
      if (task_of(seen) == task) return seen;
      const std::uint64_t next = make(generation_of(seen) + 1, task);
      if (word_.compare_exchange_weak(seen, next, std::memory_order_acq_rel, std::memory_order_acquire)) return next;
    }
  }

  // `task` takes the motion only if nobody owns it; the new word in `out`.
  bool take_if_free(std::uint8_t task, std::uint64_t& out) noexcept {
    std::uint64_t seen = word_.load(std::memory_order_acquire);
    if (task_of(seen) != kNoOwnerTask || held_for_operator(seen)) return false;
    const std::uint64_t next = make(generation_of(seen) + 1, task);
    if (!word_.compare_exchange_strong(seen, next, std::memory_order_acq_rel, std::memory_order_acquire)) return false;
    out = next;
    return true;
  }

  // Frees the motion if the word is still `expected` (nobody took it meanwhile).
  bool release(std::uint64_t expected) noexcept {
    if (task_of(expected) == kNoOwnerTask) return false;
    return word_.compare_exchange_strong(expected, make(generation_of(expected) + 1, kNoOwnerTask),
                                         std::memory_order_acq_rel, std::memory_order_acquire);
  }

  // Frees the motion if the word is still `expected`, held for the operator's take().
  bool release_to_operator(std::uint64_t expected) noexcept {
    if (task_of(expected) == kNoOwnerTask) return false;
    return word_.compare_exchange_strong(expected, make(generation_of(expected) + 1, kNoOwnerTask) | kHeldForOperator,
                                         std::memory_order_acq_rel, std::memory_order_acquire);
  }

 private:
  std::atomic<std::uint64_t> word_{kNobody};
};

}  // namespace rescue::app
