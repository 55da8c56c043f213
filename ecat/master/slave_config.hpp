// Register images the master writes into a slave's ESC during bring-up: SyncManager and FMMU
// entries (ETG.1000.4 tables 57 and 59; byte layout in ecat/codec/registers.hpp), each field stored
// little-endian through core/base/endian.hpp (constexpr, so the entries can be built at compile time).
#pragma once

#include <array>
#include <cstdint>

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat {

using SyncManagerEntry = std::array<std::uint8_t, reg::kSyncManagerSize>;
using FmmuEntry = std::array<std::uint8_t, reg::kFmmuSize>;

// SyncManager control bytes real masters use when the SII does not give them.
constexpr std::uint8_t kSmControlMailboxOut = 0x26;  // mailbox, master writes, PDI interrupt
constexpr std::uint8_t kSmControlMailboxIn = 0x22;   // mailbox, master reads, PDI interrupt
constexpr std::uint8_t kSmControlOutputs = 0x64;     // buffered, master writes, watchdog, PDI interrupt
constexpr std::uint8_t kSmControlInputs = 0x20;      // buffered, master reads, PDI interrupt

constexpr SyncManagerEntry sync_manager_entry(std::uint16_t start, std::uint16_t length, std::uint8_t control,
                                              bool enable = true) noexcept {
  SyncManagerEntry e{};
  store_le16(e.data() + reg::kSmPhysicalStart, start);
  store_le16(e.data() + reg::kSmLength, length);
  e[reg::kSmControl] = control;
  e[reg::kSmActivate] = enable ? reg::kSmEnable : 0;
  return e;
}

// Maps `length` bytes at logical `logical` onto physical `physical` (whole bytes, bits 0..7).
constexpr FmmuEntry fmmu_entry(std::uint32_t logical, std::uint16_t length, std::uint16_t physical,
                               std::uint8_t type) noexcept {
  FmmuEntry e{};
  store_le32(e.data() + reg::kFmmuLogicalStart, logical);
  store_le16(e.data() + reg::kFmmuLength, length);
  e[reg::kFmmuLogicalStartBit] = 0;
  e[reg::kFmmuLogicalStopBit] = 7;
  store_le16(e.data() + reg::kFmmuPhysicalStart, physical);
  e[reg::kFmmuPhysicalStartBit] = 0;
  e[reg::kFmmuType] = type;
  e[reg::kFmmuActivate] = 1;
  return e;
}

// FMMU0 = outputs, FMMU1 = inputs. Writing this many zero bytes at 0x060C switches off the
// activation of both (0x060C and 0x061C) and nothing that matters in between.
constexpr std::uint16_t kFmmuOutputs = 0;
constexpr std::uint16_t kFmmuInputs = 1;
constexpr std::uint16_t kFmmuActivationOffAddress = reg::fmmu(kFmmuOutputs) + reg::kFmmuActivate;
constexpr std::uint16_t kFmmuActivationOffLength = reg::kFmmuSize + 1;

}  // namespace rescue::ecat
