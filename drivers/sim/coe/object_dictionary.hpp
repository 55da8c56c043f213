// A CANopen object dictionary of fixed size: a constexpr table of entries (index, subindex, type,
// size, access) over a byte array that holds every value little-endian, as it travels in an SDO.
// No heap; the table and the storage are the device's.
//
// read()/write() are what the SDO server calls: they return the SDO abort code a real device
// gives (0 = done): object or subindex missing, read-only, wrong length, not writable in this
// EtherCAT state, or the device's own value check (a Validator). The typed get/set are the
// application's access (no state or access checks; the entry must exist, asserted).
//
// Speed: the device's cyclic path (process data mirrored in, settings read out, every cycle of
// every drive) must not search the table. It resolves the entries it uses once, at compile time
// (object_entry() over its constexpr table), and uses the get/set overloads taking an entry: a
// load or store at a fixed offset. Lookups by (index, subindex) are for SDO transfers and tests:
// a binary search of the sorted table.
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>

#include "core/base/endian.hpp"
#include "core/base/span.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {

enum class Access : std::uint8_t {
  ro,        // read only
  rw,        // read and write in any state
  rw_preop,  // writable only in PRE-OP (PDO assignment and mapping): 0x08000022 otherwise
};

struct ObjectEntry {
  std::uint16_t index;
  std::uint8_t subindex;
  std::uint16_t data_type;  // drivers/joint/joint_drive_pdo.hpp data_type codes
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

// The entry (index, subindex) of a constexpr table, for resolving fixed objects at compile time:
// an object that is not in the table runs past its end, which does not compile as a constant.
template <std::size_t N>
constexpr const ObjectEntry& object_entry(const std::array<ObjectEntry, N>& entries, std::uint16_t index,
                                          std::uint8_t subindex) noexcept {
  std::size_t i = 0;
  while (entries[i].index != index || entries[i].subindex != subindex) ++i;
  return entries[i];
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
  std::uint32_t get_u32(std::uint16_t index, std::uint8_t subindex) const noexcept { return get_u32(entry(index, subindex)); }
  std::int32_t get_i32(std::uint16_t index, std::uint8_t subindex) const noexcept { return get_i32(entry(index, subindex)); }
  void set(std::uint16_t index, std::uint8_t subindex, std::uint32_t value) noexcept { set(entry(index, subindex), value); }
  void set_string(std::uint16_t index, std::uint8_t subindex, const char* text) noexcept;

  // The same through an entry of this dictionary's table (resolved once, e.g. by object_entry()).
  std::uint32_t get_u32(const ObjectEntry& e) const noexcept {  // any size <= 4, zero-extended
    const std::uint8_t* p = value_of(e);
    switch (e.size) {
      case 1: return p[0];
      case 2: return load_le16(p);
      default: return load_le32(p);
    }
  }
  std::int32_t get_i32(const ObjectEntry& e) const noexcept {  // any size <= 4, sign-extended
    const std::uint32_t raw = get_u32(e);
    switch (e.size) {
      case 1: return static_cast<std::int8_t>(raw);
      case 2: return static_cast<std::int16_t>(raw);
      default: return static_cast<std::int32_t>(raw);
    }
  }
  void set(const ObjectEntry& e, std::uint32_t value) noexcept {  // low `size` bytes
    std::uint8_t* p = value_of(e);
    switch (e.size) {
      case 1: p[0] = static_cast<std::uint8_t>(value); break;
      case 2: store_le16(p, static_cast<std::uint16_t>(value)); break;
      default: store_le32(p, value); break;
    }
  }

  Span<const ObjectEntry> entries() const noexcept { return entries_; }

 private:
  const ObjectEntry& entry(std::uint16_t index, std::uint8_t subindex) const noexcept;
  // The value bytes of a numeric entry of this table (1, 2 or 4 bytes; asserted).
  const std::uint8_t* value_of(const ObjectEntry& e) const noexcept {
    assert(&e >= entries_.begin() && &e < entries_.end() && (e.size == 1 || e.size == 2 || e.size == 4));
    return storage_.data() + e.offset;
  }
  std::uint8_t* value_of(const ObjectEntry& e) noexcept {
    assert(&e >= entries_.begin() && &e < entries_.end() && (e.size == 1 || e.size == 2 || e.size == 4));
    return storage_.data() + e.offset;
  }

  Span<const ObjectEntry> entries_;
  ByteSpan storage_;
  Validator validator_;
};

}  // namespace rescue::drivers
