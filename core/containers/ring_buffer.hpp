// RingBuffer<T, N>: a first-in first-out buffer of at most N elements stored in place, for one
// thread (histories, pending messages, last-N samples). push() on a full buffer refuses with false;
// push_overwrite() drops the oldest element instead, for "keep the latest N" uses. Never allocates.
// For two threads or two processes use SpscQueue (core/concurrency/spsc_queue.hpp).
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <type_traits>
#include <utility>

namespace rescue {

template <typename T, std::size_t N>
class RingBuffer {
  static_assert(N > 0, "RingBuffer needs a capacity");
  // Storage is a std::array so every slot is always a live T: no placement-new lifetime rules to
  // get wrong. The price is that T must be default-constructible; firmware records are.
  static_assert(std::is_default_constructible_v<T>, "RingBuffer slots are default-constructed");

 public:
  using value_type = T;

  static constexpr std::size_t capacity() noexcept { return N; }
  std::size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }
  bool full() const noexcept { return size_ == N; }

  // Appends at the back. Returns false (and changes nothing) when full.
  [[nodiscard]] bool push(const T& value) noexcept {
    if (full()) return false;
    slots_[index(size_)] = value;
    ++size_;
    return true;
  }

  // Appends at the back; when full, the oldest element is dropped to make room. Returns true when
  // an element was dropped, so callers can count losses.
  bool push_overwrite(const T& value) noexcept {
    if (!full()) {
      slots_[index(size_)] = value;
      ++size_;
      return false;
    }
    slots_[head_] = value;
    head_ = next(head_);
    return true;
  }

  // Removes the oldest element into `out`. Returns false when empty.
  [[nodiscard]] bool pop(T& out) noexcept {
    if (empty()) return false;
    out = std::move(slots_[head_]);
    drop_front();
    return true;
  }

  // Removes the oldest element (asserted non-empty).
  void drop_front() noexcept {
    assert(size_ > 0);
    head_ = next(head_);
    --size_;
  }

  void clear() noexcept {
    head_ = 0;
    size_ = 0;
  }

  // Element i counted from the oldest (0) to the newest (size() - 1).
  T& operator[](std::size_t i) noexcept {
    assert(i < size_);
    return slots_[index(i)];
  }
  const T& operator[](std::size_t i) const noexcept {
    assert(i < size_);
    return slots_[index(i)];
  }
  T& front() noexcept { return (*this)[0]; }
  const T& front() const noexcept { return (*this)[0]; }
  T& back() noexcept { return (*this)[size_ - 1]; }
  const T& back() const noexcept { return (*this)[size_ - 1]; }

 private:
  // Wraps without a division: both operands are below N.
  static constexpr std::size_t wrap(std::size_t i) noexcept { return i >= N ? i - N : i; }
  static constexpr std::size_t next(std::size_t i) noexcept { return wrap(i + 1); }
  std::size_t index(std::size_t offset) const noexcept { return wrap(head_ + offset); }

  std::array<T, N> slots_{};
  std::size_t head_{0};  // slot of the oldest element
  std::size_t size_{0};
};

}  // namespace rescue
