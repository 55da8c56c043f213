// The fifteen EtherCAT datagram commands (ETG.1000.4 table 5) and how each one addresses slaves.
#pragma once

#include <cstdint>

namespace rescue::ecat {

enum class Command : std::uint8_t {
  NOP = 0,
  APRD = 1,   // auto-increment physical read
  APWR = 2,   // auto-increment physical write
  APRW = 3,   // auto-increment physical read-write
  FPRD = 4,   // configured-address physical read
  FPWR = 5,
  FPRW = 6,
  BRD = 7,    // broadcast read (data ORed)
  BWR = 8,
  BRW = 9,
  LRD = 10,   // logical read
  LWR = 11,
  LRW = 12,
  ARMW = 13,  // auto-increment read, multiple write (DC reference time distribution)
  FRMW = 14,  // configured-address read, multiple write
};

constexpr std::uint8_t kCommandCount = 15;

enum class AddressKind : std::uint8_t {
  none,       // NOP: the address is ignored
  position,   // ADP = -(auto-increment position), ADO = register
  station,    // ADP = configured station address, ADO = register
  broadcast,  // ADP incremented by every slave, ADO = register
  logical,    // 32-bit logical address through FMMUs
};

constexpr AddressKind address_kind(Command c) noexcept {
  switch (c) {
    case Command::NOP: return AddressKind::none;
    case Command::APRD: case Command::APWR: case Command::APRW: case Command::ARMW: return AddressKind::position;
    case Command::FPRD: case Command::FPWR: case Command::FPRW: case Command::FRMW: return AddressKind::station;
    case Command::BRD: case Command::BWR: case Command::BRW: return AddressKind::broadcast;
    case Command::LRD: case Command::LWR: case Command::LRW: return AddressKind::logical;
  }
  return AddressKind::none;
}

constexpr bool is_valid_command(std::uint8_t raw) noexcept { return raw < kCommandCount; }

// Reads slave memory into the datagram (xxRD, xxRW, ARMW/FRMW for the addressed slave).
constexpr bool reads_slave(Command c) noexcept {
  switch (c) {
    case Command::APRD: case Command::FPRD: case Command::BRD: case Command::LRD:
    case Command::APRW: case Command::FPRW: case Command::BRW: case Command::LRW:
    case Command::ARMW: case Command::FRMW: return true;
    default: return false;
  }
}

// Writes datagram data into slave memory.
constexpr bool writes_slave(Command c) noexcept {
  switch (c) {
    case Command::APWR: case Command::FPWR: case Command::BWR: case Command::LWR:
    case Command::APRW: case Command::FPRW: case Command::BRW: case Command::LRW:
    case Command::ARMW: case Command::FRMW: return true;
    default: return false;
  }
}

// Mnemonic as Wireshark and ETG.1000 print it ("FPRD"); "?" for values outside the enum.
const char* mnemonic(Command c) noexcept;

// Parses a mnemonic; false when unknown.
bool command_from_mnemonic(const char* text, Command& out) noexcept;

// 32-bit datagram address from its two 16-bit halves (ADP in the low half on the wire).
constexpr std::uint32_t make_address(std::uint16_t adp, std::uint16_t ado) noexcept {
  return static_cast<std::uint32_t>(adp) | (static_cast<std::uint32_t>(ado) << 16);
}
// ADP for auto-increment addressing of the slave at `position` (0, 0xFFFF, 0xFFFE, ...).
constexpr std::uint16_t position_adp(std::uint16_t position) noexcept {
  return static_cast<std::uint16_t>(0x10000U - position);
}
constexpr std::uint16_t address_adp(std::uint32_t address) noexcept { return static_cast<std::uint16_t>(address); }
constexpr std::uint16_t address_ado(std::uint32_t address) noexcept { return static_cast<std::uint16_t>(address >> 16); }

}  // namespace rescue::ecat
