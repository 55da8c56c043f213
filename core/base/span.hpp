// A non-owning view of contiguous elements (C++17 has no std::span). Used for every byte buffer
// handed between layers: the view never allocates and never outlives the buffer it points into.
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>

namespace rescue {

template <typename T>
class Span {
 public:
  constexpr Span() noexcept = default;
  constexpr Span(T* data, std::size_t size) noexcept : data_(data), size_(size) {}
  template <std::size_t N>
  constexpr Span(T (&array)[N]) noexcept : data_(array), size_(N) {}  // NOLINT(google-explicit-constructor,cppcoreguidelines-avoid-c-arrays,modernize-avoid-c-arrays)
  template <typename U, std::size_t N>
  constexpr Span(std::array<U, N>& array) noexcept : data_(array.data()), size_(N) {}  // NOLINT(google-explicit-constructor)
  template <typename U, std::size_t N>
  constexpr Span(const std::array<U, N>& array) noexcept : data_(array.data()), size_(N) {}  // NOLINT(google-explicit-constructor)
  // Span<const T> from Span<T>.
  template <typename U>
  constexpr Span(Span<U> other) noexcept : data_(other.data()), size_(other.size()) {}  // NOLINT(google-explicit-constructor)

  constexpr T* data() const noexcept { return data_; }
  constexpr std::size_t size() const noexcept { return size_; }
  constexpr bool empty() const noexcept { return size_ == 0; }
  constexpr T* begin() const noexcept { return data_; }
  constexpr T* end() const noexcept { return data_ + size_; }
  constexpr T& operator[](std::size_t i) const noexcept {
    assert(i < size_);
    return data_[i];
  }
  // Sub-view; the caller has checked the range (asserted).
  constexpr Span subspan(std::size_t offset, std::size_t count) const noexcept {
    assert(offset <= size_ && count <= size_ - offset);
    return Span(data_ + offset, count);
  }
  constexpr Span first(std::size_t count) const noexcept { return subspan(0, count); }

 private:
  T* data_{nullptr};
  std::size_t size_{0};
};

using ByteSpan = Span<std::uint8_t>;
using ConstByteSpan = Span<const std::uint8_t>;

}  // namespace rescue
