#include "drivers/sim/esc/esc_sii.hpp"

#include <algorithm>
#include <cstring>

#include "core/base/endian.hpp"
#include "drivers/sim/devices/minimal_sii.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

namespace reg = ecat::reg;
constexpr std::uint16_t kWritableControlBits = reg::kSiiWriteEnable | reg::kSiiCommandMask;
constexpr std::uint16_t kErrorBits = reg::kSiiCommandError | reg::kSiiWriteError;
constexpr std::uint32_t kBlock = reg::kSiiControl;  // 0x0502..0x050F

}  // namespace

void EscSii::power_up(EscMemory& memory, const EscConfig& config, ConstByteSpan image) noexcept {
  eeprom_.fill(0xFF);
  const std::size_t copied = std::min(image.size(), eeprom_.size());
  if (copied > 0) std::memcpy(eeprom_.data(), image.data(), copied);
  std::size_t declared = 0;
  if (copied >= 2U * ecat::sii::kEepromSize + 2U) {
    declared = (std::size_t{word(ecat::sii::kEepromSize)} + 1U) * 128U;
  }
  size_ = std::min(std::max(declared, (copied + 1U) & ~std::size_t{1}), eeprom_.size());
  configuration_valid_ = copied >= 16 && sii_config_crc(ConstByteSpan(eeprom_.data(), 14)) == eeprom_[14];
  read_bytes_ = config.sii_read_bytes == 4 ? 4 : 8;
  read_busy_ns_ = config.sii_read_busy_ns;
  write_busy_ns_ = config.sii_write_busy_ns;
  pending_ = false;
  busy_ = false;
  command_ = 0;
  reload_done_ = false;

  std::uint16_t status = 0;
  if (read_bytes_ == 8) status |= reg::kSiiRead8Bytes;
  if (size_ > 2048) status |= reg::kSiiTwoAddressBytes;
  if (!configuration_valid_) status |= reg::kSiiChecksumError | reg::kSiiDeviceInfoError;
  memory.set_u16(reg::kSiiControl, status);
}

std::uint16_t EscSii::word(std::uint32_t address) const noexcept {
  const std::size_t at = std::size_t{2} * address;
  if (at + 1 >= eeprom_.size()) return 0xFFFF;
  return load_le16(eeprom_.data() + at);
}

void EscSii::set_word(std::uint32_t address, std::uint16_t value) noexcept {
  const std::size_t at = std::size_t{2} * address;
  if (at + 1 >= eeprom_.size()) return;
  store_le16(eeprom_.data() + at, value);
}

void EscSii::on_master_write(EscMemory& memory, const std::uint8_t* written, const bool* mask) noexcept {
  if (busy_) return;  // the interface ignores writes while a command runs
  // Address and data registers: plain storage.
  for (std::uint32_t i = 2; i < 14; ++i) {
    if (mask[i]) memory.set_u8(kBlock + i, written[i]);
  }
  if (!mask[0] && !mask[1]) return;
  const std::uint16_t old = memory.u16(kBlock);
  std::uint16_t value = old;
  if (mask[0]) value = static_cast<std::uint16_t>((value & 0xFF00U) | written[0]);
  if (mask[1]) value = static_cast<std::uint16_t>((value & 0x00FFU) | (static_cast<unsigned>(written[1]) << 8U));
  // Only write enable and the command are writable; any control write clears the error bits.
  const auto control =
      static_cast<std::uint16_t>((old & ~(kWritableControlBits | kErrorBits)) | (value & kWritableControlBits));
  memory.set_u16(kBlock, control);
  pending_ = (control & reg::kSiiCommandMask) != 0;
}

void EscSii::start_pending(EscMemory& memory, hal::Nanoseconds now) noexcept {
  if (!pending_ || busy_) return;
  pending_ = false;
  std::uint16_t control = memory.u16(kBlock);
  command_ = control & reg::kSiiCommandMask;
  const std::uint32_t address = memory.u32(reg::kSiiAddress);
  const std::size_t words = size_ / 2;
  std::uint16_t error = 0;
  hal::Nanoseconds duration = read_busy_ns_;
  if (command_ == reg::kSiiCommandRead) {
    if (address >= words) error = reg::kSiiCommandError;
  } else if (command_ == reg::kSiiCommandWrite) {
    if ((control & reg::kSiiWriteEnable) == 0) {
      error = reg::kSiiWriteError;
    } else if (address >= words) {
      error = reg::kSiiCommandError;
    }
    duration = write_busy_ns_;
  } else if (command_ != reg::kSiiCommandReload) {
    error = reg::kSiiCommandError;
  }
  if (error != 0) {
    control = static_cast<std::uint16_t>((control & ~(reg::kSiiCommandMask | reg::kSiiWriteEnable)) | error);
    memory.set_u16(kBlock, control);
    return;
  }
  busy_ = true;
  done_at_ = now + duration;
  memory.set_u16(kBlock, static_cast<std::uint16_t>(control | reg::kSiiBusy));
}

void EscSii::update(EscMemory& memory, hal::Nanoseconds now) noexcept {
  if (busy_ && now >= done_at_) finish(memory);
}

void EscSii::finish(EscMemory& memory) noexcept {
  busy_ = false;
  const std::uint32_t address = memory.u32(reg::kSiiAddress);
  if (command_ == reg::kSiiCommandRead) {
    for (std::uint32_t i = 0; i < read_bytes_ / 2U; ++i) {
      const std::size_t at = std::size_t{2} * (std::size_t{address} + i);
      const std::uint16_t w = at + 1 < size_ ? word(address + i) : 0xFFFF;  // erased beyond the end
      memory.set_u16(reg::kSiiData + 2U * i, w);
    }
  } else if (command_ == reg::kSiiCommandWrite) {
    set_word(address, memory.u16(reg::kSiiData));  // an address beyond the EEPROM writes nothing
  }
  if (command_ == reg::kSiiCommandReload) {
    // The ESC re-reads its configuration area (and applies it: it owns those registers).
    configuration_valid_ = sii_config_crc(ConstByteSpan(eeprom_.data(), 14)) == eeprom_[14];
    std::uint16_t status = memory.u16(kBlock);
    status = configuration_valid_ ? static_cast<std::uint16_t>(status & ~(reg::kSiiChecksumError | reg::kSiiDeviceInfoError))
                                  : static_cast<std::uint16_t>(status | reg::kSiiChecksumError | reg::kSiiDeviceInfoError);
    memory.set_u16(kBlock, status);
    reload_done_ = true;
  }
  const std::uint16_t control = memory.u16(kBlock);
  memory.set_u16(kBlock, static_cast<std::uint16_t>(control & ~(reg::kSiiBusy | reg::kSiiCommandMask | reg::kSiiWriteEnable)));
}

}  // namespace rescue::drivers
