// The ESC's physical memory as the master addresses it: 4 KiB of registers (0x0000-0x0FFF) and the
// process RAM from 0x1000, plus what each register byte is (implemented, readable, writable by the
// master). Which bytes exist depends on the ESC (number of FMMUs and SyncManagers, DC, RAM size):
// a real ESC counts a datagram in its working counter only if at least one addressed byte exists
// and may be accessed that way. Real chains show it (shared/vectors/captures/replay-dc.pcapng):
// a broadcast write to FMMU 3 counts only on slaves with more than three FMMUs, a write to the
// read-only 0x092C counts nowhere, a read of 0x0918 on an ESC without 64-bit DC counts nowhere.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/endian.hpp"
#include "drivers/sim/esc/esc_config.hpp"

namespace rescue::drivers {

constexpr std::uint32_t kEscRegisterSpace = 0x1000;
constexpr std::uint32_t kEscMemorySize = kEscRegisterSpace + kMaxProcessRamBytes;

// Attributes of one register byte, as the master (ECAT side) sees it.
namespace esc_attr {
constexpr std::uint8_t kReadable = 0x01;
constexpr std::uint8_t kWritable = 0x02;
// Written values are handed to the ESC logic, never stored as such (0x0900 latch trigger, 0x0910
// system time, error counters that clear on write, SII control).
constexpr std::uint8_t kWriteTrigger = 0x04;
}  // namespace esc_attr

class EscMemory {
 public:
  // Builds the attribute map for `config` and clears the memory.
  void reset(const EscConfig& config) noexcept;

  std::uint8_t attributes(std::uint32_t address) const noexcept {
    return address < kEscRegisterSpace ? attributes_[address] : ram_attributes(address);
  }
  bool readable(std::uint32_t address) const noexcept { return (attributes(address) & esc_attr::kReadable) != 0; }
  bool writable(std::uint32_t address) const noexcept { return (attributes(address) & esc_attr::kWritable) != 0; }
  // The first address after the process RAM.
  std::uint32_t ram_end() const noexcept { return ram_end_; }

  // Raw access for the ESC logic (callers stay inside the memory; asserted).
  std::uint8_t* at(std::uint32_t address) noexcept { return bytes_.data() + address; }
  const std::uint8_t* at(std::uint32_t address) const noexcept { return bytes_.data() + address; }
  std::uint8_t u8(std::uint32_t a) const noexcept { return bytes_[a]; }
  std::uint16_t u16(std::uint32_t a) const noexcept { return load_le16(at(a)); }
  std::uint32_t u32(std::uint32_t a) const noexcept { return load_le32(at(a)); }
  std::uint64_t u64(std::uint32_t a) const noexcept { return load_le64(at(a)); }
  void set_u8(std::uint32_t a, std::uint8_t v) noexcept { bytes_[a] = v; }
  void set_u16(std::uint32_t a, std::uint16_t v) noexcept { store_le16(at(a), v); }
  void set_u32(std::uint32_t a, std::uint32_t v) noexcept { store_le32(at(a), v); }
  void set_u64(std::uint32_t a, std::uint64_t v) noexcept { store_le64(at(a), v); }

 private:
  std::uint8_t ram_attributes(std::uint32_t address) const noexcept {
    return address < ram_end_ ? static_cast<std::uint8_t>(esc_attr::kReadable | esc_attr::kWritable) : 0;
  }
  void mark(std::uint32_t first, std::uint32_t count, std::uint8_t attributes) noexcept;

  std::uint32_t ram_end_{kEscRegisterSpace};  // first: read on every RAM access, next to the ESC's state
  std::array<std::uint8_t, kEscMemorySize> bytes_{};
  std::array<std::uint8_t, kEscRegisterSpace> attributes_{};
};

}  // namespace rescue::drivers
