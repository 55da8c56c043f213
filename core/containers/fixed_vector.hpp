// FixedVector<T, N>: a vector whose storage is an in-place array of N elements, sized at compile
// time. push_back on a full vector fails with a value (false / Status), never allocates.
#pragma once

#include <cassert>
#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>

#include "core/base/result.hpp"
#include "core/base/span.hpp"

namespace rescue {

template <typename T, std::size_t N>
class FixedVector {
  static_assert(N > 0, "FixedVector needs a capacity");

 public:
  using value_type = T;

  FixedVector() noexcept = default;
  FixedVector(const FixedVector& other) {
    for (const T& v : other) (void)push_back(v);
  }
  FixedVector& operator=(const FixedVector& other) {
    if (this != &other) {
      clear();
      for (const T& v : other) (void)push_back(v);
    }
    return *this;
  }
  // Moves element by element (the storage is in place, nothing to steal); `other` keeps its
  // moved-from elements.
  FixedVector(FixedVector&& other) noexcept {
    for (T& v : other) (void)emplace_back(std::move(v));
  }
  FixedVector& operator=(FixedVector&& other) noexcept {
    if (this != &other) {
      clear();
      for (T& v : other) (void)emplace_back(std::move(v));
    }
    return *this;
  }
  ~FixedVector() { clear(); }

  static constexpr std::size_t capacity() noexcept { return N; }
  std::size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }
  bool full() const noexcept { return size_ == N; }

  // Returns false (and changes nothing) when full.
  [[nodiscard]] bool push_back(const T& value) noexcept {
    if (full()) return false;
    new (slot(size_)) T(value);
    ++size_;
    return true;
  }
  template <typename... Args>
  [[nodiscard]] T* emplace_back(Args&&... args) noexcept {
    if (full()) return nullptr;
    T* p = new (slot(size_)) T(std::forward<Args>(args)...);
    ++size_;
    return p;
  }
  void pop_back() noexcept {
    assert(size_ > 0);
    --size_;
    data()[size_].~T();
  }
  void clear() noexcept {
    while (size_ > 0) pop_back();
  }
  // Removes element i by moving the later ones down (keeps order).
  void erase_at(std::size_t i) noexcept {
    assert(i < size_);
    for (std::size_t k = i; k + 1 < size_; ++k) data()[k] = std::move(data()[k + 1]);
    pop_back();
  }

  T* data() noexcept { return std::launder(reinterpret_cast<T*>(storage_)); }  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  const T* data() const noexcept { return std::launder(reinterpret_cast<const T*>(storage_)); }  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  T& operator[](std::size_t i) noexcept {
    assert(i < size_);
    return data()[i];
  }
  const T& operator[](std::size_t i) const noexcept {
    assert(i < size_);
    return data()[i];
  }
  T& back() noexcept { return (*this)[size_ - 1]; }
  const T& back() const noexcept { return (*this)[size_ - 1]; }
  T* begin() noexcept { return data(); }
  T* end() noexcept { return data() + size_; }
  const T* begin() const noexcept { return data(); }
  const T* end() const noexcept { return data() + size_; }
  Span<T> span() noexcept { return Span<T>(data(), size_); }
  Span<const T> span() const noexcept { return Span<const T>(data(), size_); }

 private:
  void* slot(std::size_t i) noexcept { return storage_ + i * sizeof(T); }

  alignas(T) unsigned char storage_[N * sizeof(T)]{};  // NOLINT(cppcoreguidelines-avoid-c-arrays,modernize-avoid-c-arrays)
  std::size_t size_{0};
};

}  // namespace rescue
