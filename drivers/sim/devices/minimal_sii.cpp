#include "drivers/sim/devices/minimal_sii.hpp"

#include <cstring>

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/sii/sii.hpp"

namespace rescue::drivers {

std::uint8_t sii_config_crc(ConstByteSpan first_14_bytes) noexcept {
  return ecat::sii::config_area_crc(first_14_bytes.data(), first_14_bytes.size());
}

Result<std::size_t> build_minimal_sii(ByteSpan out, const SiiIdentity& identity, const char* name) noexcept {
  const std::size_t name_length = name == nullptr ? 0 : std::strlen(name);
  if (name_length > 255) return make_error(Errc::invalid_argument, "SII name longer than 255", 0, 0);
  const std::size_t size = minimal_sii_size(name_length);
  if (out.size() < size) return make_error(Errc::capacity_exceeded, "SII buffer too small", 0, 0);
  std::memset(out.data(), 0, size);
  std::uint8_t* p = out.data();
  namespace sii = ecat::sii;
  store_le16(p + std::size_t{2} * sii::kPdiControl, identity.pdi_control);
  store_le16(p + std::size_t{2} * sii::kStationAlias, identity.station_alias);
  store_le16(p + std::size_t{2} * sii::kConfigChecksum, sii_config_crc(ConstByteSpan(p, 14)));
  store_le32(p + std::size_t{2} * sii::kVendorId, identity.vendor_id);
  store_le32(p + std::size_t{2} * sii::kProductCode, identity.product_code);
  store_le32(p + std::size_t{2} * sii::kRevision, identity.revision);
  store_le32(p + std::size_t{2} * sii::kSerial, identity.serial);
  store_le16(p + std::size_t{2} * sii::kStdRxMailboxOffset, identity.mailbox_out_offset);
  store_le16(p + std::size_t{2} * sii::kStdRxMailboxSize, identity.mailbox_out_size);
  store_le16(p + std::size_t{2} * sii::kStdTxMailboxOffset, identity.mailbox_in_offset);
  store_le16(p + std::size_t{2} * sii::kStdTxMailboxSize, identity.mailbox_in_size);
  store_le16(p + std::size_t{2} * sii::kMailboxProtocols, identity.mailbox_protocols);
  store_le16(p + std::size_t{2} * sii::kEepromSize, 1);  // 2 kbit - 1: the smallest EEPROM
  store_le16(p + std::size_t{2} * sii::kVersion, 1);

  std::size_t at = std::size_t{2} * sii::kFirstCategory;
  // Strings: count, then length-prefixed strings; the category is padded to whole words.
  const std::size_t strings_bytes = (2 + name_length + 1) & ~std::size_t{1};
  store_le16(p + at, sii::kCategoryStrings);
  store_le16(p + at + 2, static_cast<std::uint16_t>(strings_bytes / 2));
  p[at + 4] = 1;
  p[at + 5] = static_cast<std::uint8_t>(name_length);
  // SII strings are length-prefixed, not NUL-terminated.
  if (name_length > 0) std::memcpy(p + at + 6, name, name_length);  // NOLINT(bugprone-not-null-terminated-result)
  at += 4 + strings_bytes;
  // General: 16 words; the name is string 1 (order and device name).
  store_le16(p + at, sii::kCategoryGeneral);
  store_le16(p + at + 2, 16);
  p[at + 4 + 2] = 1;  // order index
  p[at + 4 + 3] = 1;  // name index
  at += 4 + 32;
  store_le16(p + at, sii::kCategoryEnd);
  at += 2;
  return at;
}

}  // namespace rescue::drivers
