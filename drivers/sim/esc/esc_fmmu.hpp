// An FMMU entry (registers 0x0600 + 16n) and the bit-exact mapping it defines between the logical
// address space of LRD/LWR/LRW datagrams and the ESC's physical memory.
//
//   logical bits  [start*8 + start_bit, (start + length - 1)*8 + stop_bit]
//   physical bits  physical_start*8 + physical_start_bit onwards, in the same order
//
// Most masters map whole bytes (start bit 0, stop bit 7, physical start bit 0); bit-wise mappings
// (several slaves sharing one logical byte) are supported too.
#pragma once

#include <cstdint>

#include "drivers/sim/esc/esc_memory.hpp"

namespace rescue::drivers {

struct EscFmmu {
  std::uint32_t logical_start{0};
  std::uint16_t length{0};
  std::uint8_t logical_start_bit{0};
  std::uint8_t logical_stop_bit{7};
  std::uint16_t physical_start{0};
  std::uint8_t physical_start_bit{0};
  std::uint8_t type{0};  // bit 0: read (slave -> master), bit 1: write (master -> slave)
  bool active{false};

  static EscFmmu load(const EscMemory& memory, unsigned index) noexcept;

  bool byte_aligned() const noexcept {
    return logical_start_bit == 0 && logical_stop_bit == 7 && physical_start_bit == 0;
  }
  // First and one-past-last logical bit the FMMU maps (64-bit: logical addresses reach 2^32 bytes).
  std::uint64_t first_bit() const noexcept { return std::uint64_t{logical_start} * 8U + logical_start_bit; }
  std::uint64_t end_bit() const noexcept {
    return length == 0 ? first_bit() : (std::uint64_t{logical_start} + length - 1U) * 8U + logical_stop_bit + 1U;
  }
};

}  // namespace rescue::drivers
