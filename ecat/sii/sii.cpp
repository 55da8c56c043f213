#include "ecat/sii/sii.hpp"

#include <numeric>

#include "core/base/endian.hpp"

namespace rescue::ecat::sii {
namespace {

std::uint32_t u32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

// A category's data: where it starts in the image and how many bytes it holds.
struct Category {
  std::uint16_t type;
  std::size_t offset;
  std::size_t size;
};

}  // namespace

// Decoders of each category; a struct so it can reach Sii's private string table.
struct SiiParser {
  static Status header(ConstByteSpan image, ChecksumPolicy policy, Sii& sii) noexcept;
  static Status strings(const Category& c, Sii& sii) noexcept;
  static Status general(const Category& c, Sii& sii) noexcept;
  static Status fmmu(const Category& c, Sii& sii) noexcept;
  static Status sync_manager(const Category& c, Sii& sii) noexcept;
  static Status pdo(const Category& c, FixedVector<Pdo, kMaxPdos>& pdos,
                    FixedVector<PdoEntry, kMaxPdoEntries>& entries, const Sii& sii) noexcept;
  static Status dc(const Category& c, Sii& sii) noexcept;
};

Status SiiParser::header(ConstByteSpan image, ChecksumPolicy policy, Sii& sii) noexcept {
  if (image.size() < kHeaderBytes) return make_error(Errc::truncated, "sii header", kConfigArea, u32(image.size()));
  const std::uint8_t* p = image.data();
  auto word = [p](std::uint16_t w) { return load_le16(p + std::size_t{2} * w); };
  auto dword = [p](std::uint16_t w) { return load_le32(p + std::size_t{2} * w); };

  ConfigArea& c = sii.config;
  c.pdi_control = word(kPdiControl);
  c.pdi_config = word(kPdiConfig);
  c.sync_impulse_length = word(kSyncImpulseLength);
  c.pdi_config2 = word(kPdiConfig2);
  c.station_alias = word(kStationAlias);
  c.checksum = p[std::size_t{2} * kConfigChecksum];
  c.computed_checksum = config_area_crc(p);
  if (policy == ChecksumPolicy::require && !c.checksum_ok()) {
    return make_error(Errc::checksum, "sii config area crc", c.checksum, c.computed_checksum);
  }

  sii.identity = Identity{dword(kVendorId), dword(kProductCode), dword(kRevision),
                          dword(kSerial)};
  auto mailbox = [&word](std::uint16_t w) {
    return MailboxArea{word(w), word(static_cast<std::uint16_t>(w + 1)), word(static_cast<std::uint16_t>(w + 2)),
                       word(static_cast<std::uint16_t>(w + 3))};
  };
  sii.bootstrap_mailbox = mailbox(kBootRxMailboxOffset);
  sii.standard_mailbox = mailbox(kStdRxMailboxOffset);
  sii.mailbox_protocols = word(kMailboxProtocols);
  sii.eeprom_size_bytes = (static_cast<std::uint32_t>(word(kEepromSize)) + 1U) * 128U;
  sii.version = word(kVersion);
  return Status::success();
}

Status SiiParser::strings(const Category& c, Sii& sii) noexcept {
  const std::uint8_t* p = sii.image_.data();
  if (c.size < 1) return make_error(Errc::truncated, "sii strings count", c.type, u32(c.offset));
  const std::size_t count = p[c.offset];
  std::size_t at = c.offset + 1;
  const std::size_t end = c.offset + c.size;
  for (std::size_t i = 0; i < count; ++i) {
    if (at >= end) return make_error(Errc::truncated, "sii string length", c.type, u32(at));
    const std::uint8_t length = p[at];
    if (end - at - 1 < length) return make_error(Errc::truncated, "sii string text", c.type, u32(at));
    if (!sii.strings_.push_back(Sii::StringRef{static_cast<std::uint16_t>(at + 1), length})) {
      return make_error(Errc::capacity_exceeded, "sii strings", c.type, u32(at));
    }
    at += 1U + length;
  }
  return Status::success();
}

Status SiiParser::general(const Category& c, Sii& sii) noexcept {
  if (c.size < kGeneralSize) return make_error(Errc::truncated, "sii general category", c.type, u32(c.offset));
  const std::uint8_t* p = sii.image_.data() + c.offset;
  General& g = sii.general;
  g.group_index = p[0];
  g.image_index = p[1];
  g.order_index = p[2];
  g.name_index = p[3];
  g.coe_details = p[5];
  g.foe_details = p[6];
  g.eoe_details = p[7];
  g.soe_channels = p[8];
  g.ds402_channels = p[9];
  g.sysman_class = p[10];
  g.flags = p[11];
  g.current_on_ebus_ma = load_le16s(p + 12);
  g.physical_ports = load_le16(p + 16);
  g.physical_memory_address = load_le16(p + 18);
  sii.has_general = true;
  return Status::success();
}

Status SiiParser::fmmu(const Category& c, Sii& sii) noexcept {
  const std::uint8_t* p = sii.image_.data() + c.offset;
  for (std::size_t i = 0; i < c.size; ++i) {
    // 0xFF pads a category to whole words; 4..0xFE are not defined and read as unused.
    const std::uint8_t raw = p[i];
    if (raw == 0xFF && i + 1 == c.size) break;
    const FmmuUsage usage = raw <= 3 ? static_cast<FmmuUsage>(raw) : FmmuUsage::unused;
    if (!sii.fmmus.push_back(usage)) return make_error(Errc::capacity_exceeded, "sii fmmus", c.type, u32(c.offset + i));
  }
  return Status::success();
}

Status SiiParser::sync_manager(const Category& c, Sii& sii) noexcept {
  if (c.size % kSyncManagerRecordSize != 0) {
    return make_error(Errc::malformed, "sii sync manager category size", c.type, u32(c.offset));
  }
  for (std::size_t at = c.offset; at < c.offset + c.size; at += kSyncManagerRecordSize) {
    const std::uint8_t* p = sii.image_.data() + at;
    SyncManager sm{load_le16(p), load_le16(p + 2), p[4], p[5], p[6], static_cast<SyncManagerType>(p[7])};
    if (p[7] > 4) sm.type = SyncManagerType::unused;
    if (!sii.sync_managers.push_back(sm)) return make_error(Errc::capacity_exceeded, "sii sync managers", c.type, u32(at));
  }
  return Status::success();
}

Status SiiParser::pdo(const Category& c, FixedVector<Pdo, kMaxPdos>& pdos, FixedVector<PdoEntry, kMaxPdoEntries>& entries,
                      const Sii& sii) noexcept {
  const std::uint8_t* image = sii.image_.data();
  std::size_t at = c.offset;
  const std::size_t end = c.offset + c.size;
  while (at < end) {
    if (end - at < kPdoHeaderSize) return make_error(Errc::truncated, "sii pdo header", c.type, u32(at));
    const std::uint8_t* p = image + at;
    Pdo record{};
    record.index = load_le16(p);
    record.entry_count = p[2];
    record.sync_manager = p[3];
    record.dc_sync = p[4];
    record.name_index = p[5];
    record.flags = load_le16(p + 6);
    record.first_entry = static_cast<std::uint16_t>(entries.size());
    at += kPdoHeaderSize;
    if ((end - at) / kPdoEntrySize < record.entry_count) return make_error(Errc::truncated, "sii pdo entries", c.type, u32(at));
    for (std::size_t e = 0; e < record.entry_count; ++e, at += kPdoEntrySize) {
      const std::uint8_t* q = image + at;
      const PdoEntry entry{load_le16(q), q[2], q[3], q[4], q[5], load_le16(q + 6)};
      record.bit_length += entry.bit_length;
      if (!entries.push_back(entry)) return make_error(Errc::capacity_exceeded, "sii pdo entries", c.type, u32(at));
    }
    if (!pdos.push_back(record)) return make_error(Errc::capacity_exceeded, "sii pdos", c.type, u32(at));
  }
  return Status::success();
}

Status SiiParser::dc(const Category& c, Sii& sii) noexcept {
  if (c.size % kDcRecordSize != 0) return make_error(Errc::malformed, "sii dc category size", c.type, u32(c.offset));
  for (std::size_t at = c.offset; at < c.offset + c.size; at += kDcRecordSize) {
    const std::uint8_t* p = sii.image_.data() + at;
    const DcMode mode{load_le32(p),      load_le32(p + 4), load_le32(p + 8), load_le16s(p + 12),
                      load_le16(p + 14), load_le16s(p + 16), p[18],          p[19]};
    if (!sii.dc_modes.push_back(mode)) return make_error(Errc::capacity_exceeded, "sii dc modes", c.type, u32(at));
  }
  return Status::success();
}

Result<Sii> Sii::parse(ConstByteSpan image, ChecksumPolicy policy) noexcept {
  Sii sii;
  sii.image_ = image;
  RESCUE_TRY(SiiParser::header(image, policy, sii));

  bool seen_strings = false;
  bool seen_general = false;
  std::size_t at = kHeaderBytes;
  const std::size_t size = image.size();
  // Each step advances at least 4 bytes, so the walk ends. An image may end without the end
  // marker when the categories fill the EEPROM exactly.
  while (size - at >= 2) {
    const std::uint16_t type = load_le16(image.data() + at);
    if (type == kCategoryEnd) {
      at += 2;
      break;
    }
    if (size - at < 4) return make_error(Errc::truncated, "sii category header", type, u32(at));
    const std::size_t bytes = std::size_t{2} * load_le16(image.data() + at + 2);
    if (size - at - 4 < bytes) return make_error(Errc::truncated, "sii category size", type, u32(at + 2));
    const Category c{type, at + 4, bytes};
    ++sii.category_count;
    switch (type) {
      case kCategoryStrings:
        if (!seen_strings) RESCUE_TRY(SiiParser::strings(c, sii));
        seen_strings = true;
        break;
      case kCategoryGeneral:
        if (!seen_general) RESCUE_TRY(SiiParser::general(c, sii));
        seen_general = true;
        break;
      case kCategoryFmmu: RESCUE_TRY(SiiParser::fmmu(c, sii)); break;
      case kCategorySyncManager: RESCUE_TRY(SiiParser::sync_manager(c, sii)); break;
      case kCategoryTxPdo: RESCUE_TRY(SiiParser::pdo(c, sii.tx_pdos, sii.tx_entries, sii)); break;
      case kCategoryRxPdo: RESCUE_TRY(SiiParser::pdo(c, sii.rx_pdos, sii.rx_entries, sii)); break;
      case kCategoryDc: RESCUE_TRY(SiiParser::dc(c, sii)); break;
      default: break;  // vendor specific, data types, sync units, ...: not needed, skipped
    }
    at = c.offset + c.size;
  }
  sii.end_offset = at;
  return sii;
}

std::string_view Sii::string(std::uint8_t index) const noexcept {
  if (index == 0 || index > strings_.size()) return {};
  const StringRef& s = strings_[index - 1U];
  return {reinterpret_cast<const char*>(image_.data() + s.offset), s.length};  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
}

Span<const PdoEntry> Sii::tx_entries_of(const Pdo& pdo) const noexcept {
  return {tx_entries.data() + pdo.first_entry, pdo.entry_count};
}

Span<const PdoEntry> Sii::rx_entries_of(const Pdo& pdo) const noexcept {
  return {rx_entries.data() + pdo.first_entry, pdo.entry_count};
}

std::uint32_t Sii::default_bits_of_sync_manager(std::uint8_t sm) const noexcept {
  auto add = [sm](std::uint32_t bits, const Pdo& p) { return p.sync_manager == sm ? bits + p.bit_length : bits; };
  return std::accumulate(rx_pdos.begin(), rx_pdos.end(), std::accumulate(tx_pdos.begin(), tx_pdos.end(), 0U, add), add);
}

const char* to_string(SyncManagerType type) noexcept {
  switch (type) {
    case SyncManagerType::unused: return "unused";
    case SyncManagerType::mailbox_out: return "mailbox out";
    case SyncManagerType::mailbox_in: return "mailbox in";
    case SyncManagerType::outputs: return "outputs";
    case SyncManagerType::inputs: return "inputs";
  }
  return "?";
}

}  // namespace rescue::ecat::sii
