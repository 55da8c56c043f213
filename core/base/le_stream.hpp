// The one sequential little-endian writer and reader of the program: wire formats written and read
// field by field (the operator protocol's codec, pcapng blocks, SII images) go through these.
// Both are bounds-checked over a caller's buffer and never allocate: an access that does not fit
// touches nothing and marks the stream failed, and a failed stream stays failed (ok() is false,
// every later access is refused, a refused read gives 0), so a caller checks ok() once at the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "core/base/endian.hpp"
#include "core/base/span.hpp"

namespace rescue {

class LeWriter {
 public:
  explicit LeWriter(ByteSpan out) noexcept : out_(out) {}

  void u8(std::uint8_t v) noexcept {
    if (room(1)) out_[at_++] = v;
  }
  void u16(std::uint16_t v) noexcept {
    if (!room(2)) return;
    store_le16(out_.data() + at_, v);
    at_ += 2;
  }
  void u32(std::uint32_t v) noexcept {
    if (!room(4)) return;
    store_le32(out_.data() + at_, v);
    at_ += 4;
  }
  void u64(std::uint64_t v) noexcept {
    if (!room(8)) return;
    store_le64(out_.data() + at_, v);
    at_ += 8;
  }
  // IEEE 754 binary64, its bits little-endian.
  void f64(double v) noexcept {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  void zeros(std::size_t count) noexcept {
    if (!room(count)) return;
    if (count > 0) std::memset(out_.data() + at_, 0, count);
    at_ += count;
  }
  void bytes(const std::uint8_t* data, std::size_t count) noexcept {
    if (!room(count)) return;
    if (count > 0) std::memcpy(out_.data() + at_, data, count);
    at_ += count;
  }
  // Characters as they are (a text field's terminator and padding are the caller's).
  void chars(const char* data, std::size_t count) noexcept {
    if (!room(count)) return;
    for (std::size_t i = 0; i < count; ++i) out_[at_ + i] = static_cast<std::uint8_t>(data[i]);
    at_ += count;
  }
  // Moves on without writing (the bytes keep what the buffer held).
  void skip(std::size_t count) noexcept {
    if (room(count)) at_ += count;
  }
  // Writes at `offset` from the start without moving on: a length patched once it is known, a
  // field at a fixed address. Bounds-checked against the whole buffer.
  void u16_at(std::size_t offset, std::uint16_t v) noexcept {
    if (fits_at(offset, 2)) store_le16(out_.data() + offset, v);
  }
  void u32_at(std::size_t offset, std::uint32_t v) noexcept {
    if (fits_at(offset, 4)) store_le32(out_.data() + offset, v);
  }

  std::size_t size() const noexcept { return at_; }  // bytes written (and skipped) so far
  bool ok() const noexcept { return ok_; }

 private:
  bool room(std::size_t count) noexcept { return fits_at(at_, count); }
  bool fits_at(std::size_t offset, std::size_t count) noexcept {
    ok_ = ok_ && offset <= out_.size() && count <= out_.size() - offset;
    return ok_;
  }

  ByteSpan out_;
  std::size_t at_{0};
  bool ok_{true};
};

class LeReader {
 public:
  explicit LeReader(ConstByteSpan in) noexcept : in_(in) {}

  std::uint8_t u8() noexcept { return room(1) ? in_[at_++] : 0; }
  std::uint16_t u16() noexcept {
    if (!room(2)) return 0;
    const std::uint16_t v = load_le16(in_.data() + at_);
    at_ += 2;
    return v;
  }
  std::uint32_t u32() noexcept {
    if (!room(4)) return 0;
    const std::uint32_t v = load_le32(in_.data() + at_);
    at_ += 4;
    return v;
  }
  std::uint64_t u64() noexcept {
    if (!room(8)) return 0;
    const std::uint64_t v = load_le64(in_.data() + at_);
    at_ += 8;
    return v;
  }
  double f64() noexcept {
    const std::uint64_t bits = u64();
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  // True when the next `count` bytes are all zero (reserved bytes); false also when they are not there.
  bool zeros(std::size_t count) noexcept {
    if (!room(count)) return false;
    bool all = true;
    for (std::size_t i = 0; i < count; ++i) all = all && in_[at_ + i] == 0;
    at_ += count;
    return all;
  }
  // The next `count` bytes into `out` (zeros when they are not there).
  void chars(char* out, std::size_t count) noexcept {
    const bool there = room(count);
    for (std::size_t i = 0; i < count; ++i) out[i] = there ? static_cast<char>(in_[at_ + i]) : '\0';
    if (there) at_ += count;
  }

  // The byte at `offset` from the start, without moving on (0 when it is not there; never a failure).
  std::uint8_t peek(std::size_t offset) const noexcept { return offset < in_.size() ? in_[offset] : 0; }

  std::size_t size() const noexcept { return at_; }  // bytes read so far
  bool ok() const noexcept { return ok_; }

 private:
  bool room(std::size_t count) noexcept {
    ok_ = ok_ && count <= in_.size() - at_;
    return ok_;
  }

  ConstByteSpan in_;
  std::size_t at_{0};
  bool ok_{true};
};

}  // namespace rescue
