// CRC-32 (IEEE 802.3 / zlib: reflected polynomial 0xEDB88320, initial value and final XOR 0xFFFFFFFF),
// table-driven, usable at compile time. It detects accidental corruption of stored data (bit rot, a
// torn or truncated write); it is not a defence against deliberate tampering.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"

namespace rescue {

namespace crc32_detail {
constexpr std::array<std::uint32_t, 256> make_table() noexcept {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}
constexpr std::array<std::uint32_t, 256> kTable = make_table();
}  // namespace crc32_detail

// Incremental form: Crc32 c; c.update(a); c.update(b); c.value().
class Crc32 {
 public:
  constexpr void update(std::uint8_t byte) noexcept {
    state_ = crc32_detail::kTable[(state_ ^ byte) & 0xFFU] ^ (state_ >> 8);
  }
  constexpr void update(ConstByteSpan bytes) noexcept {
    for (const std::uint8_t b : bytes) update(b);
  }
  constexpr std::uint32_t value() const noexcept { return state_ ^ 0xFFFFFFFFU; }

 private:
  std::uint32_t state_{0xFFFFFFFFU};
};

constexpr std::uint32_t crc32(ConstByteSpan bytes) noexcept {
  Crc32 c;
  c.update(bytes);
  return c.value();
}

}  // namespace rescue
