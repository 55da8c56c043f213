// Writes an SII (EEPROM) image the way real devices carry it: the 64-word header with the
// config-area CRC, then categories (type, size in words, data padded to a whole word), then the
// end marker; unused EEPROM reads 0xFF. Layout constants are those of ecat/sii/sii.hpp and
// ecat/codec/registers.hpp, so what this writes is what ecat::sii::Sii::parse reads back.
//
// Every write goes through the bounds-checked little-endian writer (core/base/le_stream.hpp): a
// write that does not fit marks the writer failed (the first failure is kept) instead of writing
// past the buffer; finish() reports it.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/le_stream.hpp"
#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/sii/sii.hpp"

namespace rescue::drivers {

// The fixed header (words 0x00..0x3F).
struct SiiHeader {
  std::uint16_t pdi_control{0};
  std::uint16_t pdi_config{0};
  std::uint16_t sync_impulse_length{0};
  std::uint16_t pdi_config2{0};
  std::uint16_t station_alias{0};
  ecat::sii::Identity identity{};
  ecat::sii::MailboxArea bootstrap_mailbox{};
  ecat::sii::MailboxArea standard_mailbox{};
  std::uint16_t mailbox_protocols{0};
  std::uint16_t eeprom_size_word{0x000F};  // (KiBit - 1): 0x0F = 16 KiBit = 2 KiB
  std::uint16_t version{1};
};

class SiiWriter {
 public:
  // Fills `image` with 0xFF (erased EEPROM) and writes the header with its CRC.
  SiiWriter(ByteSpan image, const SiiHeader& header) noexcept;

  // Categories: open, write the data, close (pads to a whole word and stores the size).
  void begin_category(std::uint16_t type) noexcept;
  void end_category() noexcept;

  void u8(std::uint8_t v) noexcept;
  void u16(std::uint16_t v) noexcept;
  void u32(std::uint32_t v) noexcept;
  void zeros(std::size_t count) noexcept;
  // A Strings category entry: length byte, then the characters (no terminator).
  void string(const char* text) noexcept;

  // Writes the end marker; returns the bytes used (header and categories) or the first failure.
  Result<std::size_t> finish() noexcept;

 private:
  ByteSpan image_;
  LeWriter w_;                     // the header's words, then the categories (all but the end marker's 2 bytes)
  std::size_t category_start_{0};  // offset of the open category's header, 0 when none is open
  Status status_{};
};

// Helpers for the General category (32 bytes) and the other fixed records.
struct SiiGeneral {
  std::uint8_t group_index{0};
  std::uint8_t image_index{0};
  std::uint8_t order_index{0};
  std::uint8_t name_index{0};
  std::uint8_t coe_details{0};
  std::uint8_t ds402_channels{0};
  std::uint8_t flags{0};
  std::int16_t current_on_ebus_ma{0};
  std::uint16_t physical_ports{0};
};
void write_general(SiiWriter& w, const SiiGeneral& g) noexcept;
void write_sync_manager(SiiWriter& w, const ecat::sii::SyncManager& sm) noexcept;
void write_dc_mode(SiiWriter& w, const ecat::sii::DcMode& mode) noexcept;

}  // namespace rescue::drivers
