// A minimal SII (EEPROM) image for devices that need nothing more than an identity and a name:
// the 64-word header (ESC configuration area with its CRC, identity, no mailbox, size, version),
// a Strings category holding the name and a General category pointing at it, then End.
// Used for the junction slaves and the ESC tests; the joint drives' full images (mailbox, SM, FMMU,
// PDO categories) come from their device model.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"

namespace rescue::drivers {

struct SiiIdentity {
  std::uint32_t vendor_id{0};
  std::uint32_t product_code{0};
  std::uint32_t revision{0};
  std::uint32_t serial{0};
  std::uint16_t station_alias{0};  // word 4: loaded into 0x0012 at power-up
  std::uint16_t pdi_control{0};    // word 0: 0x0140 PDI control, 0x0141 ESC configuration
  // Standard mailbox (words 0x18..0x1C); sizes 0: no mailbox.
  std::uint16_t mailbox_out_offset{0};  // master -> slave (SM0)
  std::uint16_t mailbox_out_size{0};
  std::uint16_t mailbox_in_offset{0};   // slave -> master (SM1)
  std::uint16_t mailbox_in_size{0};
  std::uint16_t mailbox_protocols{0};
};

// CRC-8 of the ESC configuration area (words 0..6), polynomial x^8+x^2+x+1, initial value 0xFF,
// as ESCs check it at power-up (stored in the low byte of word 7).
std::uint8_t sii_config_crc(ConstByteSpan first_14_bytes) noexcept;

constexpr std::size_t constexpr_length(const char* text) noexcept {
  std::size_t n = 0;
  while (text[n] != '\0') ++n;
  return n;
}

// Bytes a minimal image with a name of `name_length` characters needs.
constexpr std::size_t minimal_sii_size(std::size_t name_length) noexcept {
  // header 128 + strings (4 + 1 + 1 + name, padded to a word) + general (4 + 32) + end (2)
  return 128 + ((4 + 2 + name_length + 1) & ~std::size_t{1}) + 36 + 2;
}

// Writes the image into `out` and returns its length in bytes; capacity_exceeded when `out` is too
// small, invalid_argument for a name longer than 255 characters.
Result<std::size_t> build_minimal_sii(ByteSpan out, const SiiIdentity& identity, const char* name) noexcept;

}  // namespace rescue::drivers
