// A CANopen object dictionary of fixed size: a constexpr table of entries (index, subindex, type,
// size, access) over a byte array that holds every value little-endian, as it travels in an SDO.
// No heap; the table and the storage are the device's.
//
// read()/write() are what the SDO server calls: they return the SDO abort code a real device
// gives (0 = done): object or subindex missing, read-only, wrong length, not writable in this
// EtherCAT state, or the device's own value check (a Validator). The typed get/set are the
// application's access (no state or access checks; the entry must exist, asserted).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/span.hpp"
#include "ecat/registers.hpp"

namespace rescue::drivers {

enum class Access : std::uint8_t {
  ro,        // read only
  rw,        // read and write in any state
  rw_preop,  // writable only in PRE-OP (PDO assignment and mapping): 0x08000022 otherwise
};

struct ObjectEntry {
  std::uint16_t index;
  std::uint8_t subindex;
  std::uint16_t data_type;  // drivers/joint_drive_pdo.hpp data_type codes
  std::uint8_t size;        // bytes (capacity for visible strings)
  Access access;
  std::uint16_t offset;     // in the storage array
  const char* name;
};

// Gives each entry its offset (in table order) at compile time; returns the storage bytes needed.
template <std::size_t N>
constexpr std::size_t assign_offsets(std::array<ObjectEntry, N>& entries) noexcept {
  std::size_t offset = 0;
  for (ObjectEntry& e : entries) {
    e.offset = static_cast<std::uint16_t>(offset);
    offset += e.size;
  }
  return offset;
}

// Entries sorted by (index, subindex), every index starting at subindex 0: what find() relies on.
template <std::size_t N>
constexpr bool entries_are_sorted(const std::array<ObjectEntry, N>& entries) noexcept {
  for (std::size_t i = 1; i < N; ++i) {
    const auto a = (static_cast<std::uint32_t>(entries[i - 1].index) << 8U) | entries[i - 1].subindex;
    const auto b = (static_cast<std::uint32_t>(entries[i].index) << 8U) | entries[i].subindex;
    if (a >= b) return false;
    if (entries[i].index != entries[i - 1].index && entries[i].subindex != 0) return false;
  }
  return N == 0 || entries[0].subindex == 0;
}

// What an SDO upload reads: an abort code, or the bytes (a view into the storage).
struct ObjectRead {
  std::uint32_t abort_code{0};
  ConstByteSpan bytes{};
};

class ObjectDictionary;
// A device's own check of a value about to be written (range, mapping content, ...): 0 accepts,
// otherwise the abort code. Runs after the generic checks (existence, access, state, length).
using Validator = std::uint32_t (*)(const ObjectDictionary& od, const ObjectEntry& entry, ConstByteSpan value) noexcept;

class ObjectDictionary {
 public:
  ObjectDictionary(Span<const ObjectEntry> entries, ByteSpan storage, Validator validator) noexcept;

  const ObjectEntry* find(std::uint16_t index, std::uint8_t subindex) const noexcept;
  bool has_index(std::uint16_t index) const noexcept;

  ObjectRead read(std::uint16_t index, std::uint8_t subindex) const noexcept;
  std::uint32_t write(std::uint16_t index, std::uint8_t subindex, ConstByteSpan value, ecat::reg::AlState state) noexcept;

  // Application access (entry must exist; sizes must match, asserted).
  std::uint32_t get_u32(std::uint16_t index, std::uint8_t subindex) const noexcept;  // any size <= 4, zero-extended
  std::int32_t get_i32(std::uint16_t index, std::uint8_t subindex) const noexcept;   // any size <= 4, sign-extended
  void set(std::uint16_t index, std::uint8_t subindex, std::uint32_t value) noexcept;  // low `size` bytes
  void set_string(std::uint16_t index, std::uint8_t subindex, const char* text) noexcept;

  Span<const ObjectEntry> entries() const noexcept { return entries_; }

 private:
  const ObjectEntry& entry(std::uint16_t index, std::uint8_t subindex) const noexcept;

  Span<const ObjectEntry> entries_;
  ByteSpan storage_;
  Validator validator_;
};

}  // namespace rescue::drivers
