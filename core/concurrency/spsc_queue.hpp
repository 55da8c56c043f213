// SpscQueue<T, N>: a wait-free queue for exactly one producer and one consumer, which may be two
// threads or two processes sharing the object through POSIX shared memory (shm_open + mmap).
//
// Why it works across processes:
//  - no pointers inside: the slots are an in-place array, positions are 64-bit counters, so each
//    process may map the segment at a different address;
//  - the only synchronisation is std::atomic<std::uint64_t> that is always lock-free, hence
//    address-free (C++17 [atomics.lockfree]/4): it works on memory mapped twice;
//  - the type is standard-layout and trivially destructible: a process may create it in place once
//    (create_at) and others attach to the same bytes (attach), nobody needs to run a destructor;
//  - payloads are trivially copyable, so copying them through the slot is a plain byte copy.
//
// Memory ordering (head = next slot to read, owned by the consumer; tail = next slot to write, owned
// by the producer; both only grow, the slot is counter % N):
//  - push writes the slot, then tail.store(release); pop does tail.load(acquire) before reading the
//    slot, so the consumer sees the payload complete.
//  - pop reads the slot, then head.store(release); push does head.load(acquire) before reusing a
//    slot, so the producer never overwrites a slot the consumer is still reading.
//  - each side keeps a private cached copy of the other side's counter and reloads it only when the
//    queue looks full (producer) or empty (consumer): the shared line is touched once per batch.
// Counters are 64 bits: at 10^9 operations per second they wrap after 584 years.
//
// The counters live in shared memory that a stray write or a bit flip may damage
// (docs/shared-memory.md "A damaged segment"). Both sides always see tail - head <= N (the producer
// never runs more than N ahead of the head it saw; head never passes a tail the consumer saw), so a
// pair that breaks it is damage: push and pop refuse it (false: nothing written, nothing read, never
// 2^63 "entries" drained) and corrupt() says so; a cached copy that breaks it is reloaded.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>

#include "core/base/result.hpp"

namespace rescue {

// One cache line: head and tail live on separate lines so producer and consumer do not false-share.
inline constexpr std::size_t kCacheLine = 64;

template <typename T, std::size_t N>
class SpscQueue {
  static_assert(N >= 2 && (N & (N - 1)) == 0, "SpscQueue capacity must be a power of two");
  static_assert(std::is_trivially_copyable_v<T>, "SpscQueue payloads are copied as bytes between processes");
  static_assert(std::is_default_constructible_v<T>, "SpscQueue slots are value-initialised");
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free,
                "shared-memory queues need lock-free (address-free) 64-bit atomics");

 public:
  using value_type = T;

  SpscQueue() noexcept {
    // Checked here, where the class is complete: what makes it safe to place in shared memory.
    static_assert(std::is_standard_layout_v<SpscQueue>, "shared-memory objects must be standard-layout");
    static_assert(std::is_trivially_destructible_v<SpscQueue>, "processes unmap the queue without destroying it");
  }
  SpscQueue(const SpscQueue&) = delete;
  SpscQueue& operator=(const SpscQueue&) = delete;
  SpscQueue(SpscQueue&&) = delete;
  SpscQueue& operator=(SpscQueue&&) = delete;
  ~SpscQueue() = default;

  static constexpr std::size_t capacity() noexcept { return N; }

  // Constructs an empty queue in `memory` (e.g. inside a fresh shared-memory segment) and returns
  // it. `memory` must hold sizeof(SpscQueue) bytes aligned to alignof(SpscQueue).
  static Result<SpscQueue*> create_at(void* memory) noexcept {
    RESCUE_TRY(check_placement(memory));
    return new (memory) SpscQueue();
  }

  // Uses a queue that another process created with create_at() in the same bytes. Fails when the
  // bytes do not hold a queue of this element size and capacity (e.g. a different build).
  static Result<SpscQueue*> attach(void* memory) noexcept {
    RESCUE_TRY(check_placement(memory));
    auto* queue = std::launder(static_cast<SpscQueue*>(memory));
    if (queue->layout_tag_ != kLayoutTag) {
      return make_error(Errc::mismatch, "shared queue layout differs (element size or capacity)",
                        static_cast<std::uint32_t>(queue->layout_tag_ >> 32U),
                        static_cast<std::uint32_t>(queue->layout_tag_));
    }
    return queue;
  }

  // Producer only. Returns false (and changes nothing) when the queue is full.
  [[nodiscard]] bool try_push(const T& value) noexcept {
    return try_push_in_place([&value](T& slot) noexcept { slot = value; });
  }

  // Producer only: `fill(T&)` writes the payload straight into the free slot (no staging copy for
  // large payloads; the slot holds whatever an earlier payload left). False when the queue is full,
  // and `fill` is not called.
  template <typename Fill>
  [[nodiscard]] bool try_push_in_place(Fill&& fill) noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);  // our own counter
    if (tail - producer_cached_head_ >= N) {  // full, or a damaged cached copy
      producer_cached_head_ = head_.load(std::memory_order_acquire);
      if (tail - producer_cached_head_ >= N) return false;  // full (== N) or damaged (> N)
    }
    fill(slots_[slot(tail)]);
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  // Consumer only. Returns false (and leaves `out` alone) when the queue is empty.
  [[nodiscard]] bool try_pop(T& out) noexcept {
    return try_pop_in_place([&out](const T& slot) noexcept { out = slot; });
  }

  // Consumer only: `use(const T&)` reads the payload in its slot, which is released when `use`
  // returns. False when the queue is empty, and `use` is not called.
  template <typename Use>
  [[nodiscard]] bool try_pop_in_place(Use&& use) noexcept {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);  // our own counter
    if (head == consumer_cached_tail_ || consumer_cached_tail_ - head > N) {  // empty, or a damaged cached copy
      consumer_cached_tail_ = tail_.load(std::memory_order_acquire);
      if (head == consumer_cached_tail_ || consumer_cached_tail_ - head > N) return false;  // empty or damaged
    }
    use(static_cast<const T&>(slots_[slot(head)]));
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  // Either side; a snapshot that may be stale by the time the caller looks at it.
  std::size_t size_approx() const noexcept {
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    const std::uint64_t tail = tail_.load(std::memory_order_acquire);
    return tail >= head ? static_cast<std::size_t>(tail - head) : 0;
  }
  bool empty_approx() const noexcept { return size_approx() == 0; }

  // Producer or consumer only (each reads its own counter exactly; a third party may see the pair
  // in passing): the counters break tail - head <= N, which no push or pop can cause (damage: the
  // queue refuses every push and pop from then on, until a new segment).
  bool corrupt() const noexcept {
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    const std::uint64_t tail = tail_.load(std::memory_order_acquire);
    return tail - head > N;
  }

 private:
  static constexpr std::uint64_t kLayoutTag = (static_cast<std::uint64_t>(sizeof(T)) << 32U) | N;

  static std::size_t slot(std::uint64_t counter) noexcept { return static_cast<std::size_t>(counter & (N - 1)); }

  static Status check_placement(const void* memory) noexcept {
    if (memory == nullptr) return make_error(Errc::invalid_argument, "shared queue memory is null");
    if (reinterpret_cast<std::uintptr_t>(memory) % alignof(SpscQueue) != 0) {  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
      return make_error(Errc::invalid_argument, "shared queue memory is misaligned",
                        static_cast<std::uint32_t>(alignof(SpscQueue)));
    }
    return Status::success();
  }

  // Consumer's line: its counter and its cached view of the producer's.
  alignas(kCacheLine) std::atomic<std::uint64_t> head_{0};
  std::uint64_t consumer_cached_tail_{0};
  // Producer's line.
  alignas(kCacheLine) std::atomic<std::uint64_t> tail_{0};
  std::uint64_t producer_cached_head_{0};
  // Written once by create_at's constructor; attach() checks it.
  alignas(kCacheLine) std::uint64_t layout_tag_{kLayoutTag};
  alignas(kCacheLine) std::array<T, N> slots_{};
};

}  // namespace rescue
