#include "drivers/sim/devices/sii_writer.hpp"

#include <cstring>

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

std::uint8_t* word_at(ByteSpan image, std::uint16_t word) noexcept { return &image[std::size_t{2} * word]; }

}  // namespace

SiiWriter::SiiWriter(ByteSpan image, const SiiHeader& h) noexcept : image_(image), at_(ecat::sii::kHeaderBytes) {
  if (image.size() < ecat::sii::kHeaderBytes + 2) {
    status_ = make_error(Errc::capacity_exceeded, "sii image smaller than its header", 0, static_cast<std::uint32_t>(image.size()));
    return;
  }
  namespace sii = ecat::sii;
  std::memset(image.data(), 0xFF, image.size());
  std::memset(image.data(), 0, sii::kHeaderBytes);
  store_le16(word_at(image, sii::kPdiControl), h.pdi_control);
  store_le16(word_at(image, sii::kPdiConfig), h.pdi_config);
  store_le16(word_at(image, sii::kSyncImpulseLength), h.sync_impulse_length);
  store_le16(word_at(image, sii::kPdiConfig2), h.pdi_config2);
  store_le16(word_at(image, sii::kStationAlias), h.station_alias);
  store_le16(word_at(image, sii::kConfigChecksum), sii::config_area_crc(image.data()));
  store_le32(word_at(image, sii::kVendorId), h.identity.vendor_id);
  store_le32(word_at(image, sii::kProductCode), h.identity.product_code);
  store_le32(word_at(image, sii::kRevision), h.identity.revision);
  store_le32(word_at(image, sii::kSerial), h.identity.serial_number);
  const sii::MailboxArea* areas[] = {&h.bootstrap_mailbox, &h.standard_mailbox};
  const std::uint16_t first_words[] = {sii::kBootRxMailboxOffset, sii::kStdRxMailboxOffset};
  for (std::size_t i = 0; i < 2; ++i) {
    std::uint8_t* p = word_at(image, first_words[i]);
    store_le16(p, areas[i]->receive_offset);
    store_le16(p + 2, areas[i]->receive_size);
    store_le16(p + 4, areas[i]->send_offset);
    store_le16(p + 6, areas[i]->send_size);
  }
  store_le16(word_at(image, sii::kMailboxProtocols), h.mailbox_protocols);
  store_le16(word_at(image, sii::kEepromSize), h.eeprom_size_word);
  store_le16(word_at(image, sii::kVersion), h.version);
}

bool SiiWriter::room_for(std::size_t bytes) noexcept {
  if (!status_.ok()) return false;
  // Keep two bytes for the end marker.
  if (image_.size() - at_ < bytes + 2) {
    status_ = make_error(Errc::capacity_exceeded, "sii image full", static_cast<std::uint32_t>(at_),
                         static_cast<std::uint32_t>(bytes));
    return false;
  }
  return true;
}

void SiiWriter::begin_category(std::uint16_t type) noexcept {
  if (category_start_ != 0) end_category();
  if (!room_for(4)) return;
  category_start_ = at_;
  store_le16(image_.data() + at_, type);
  store_le16(image_.data() + at_ + 2, 0);
  at_ += 4;
}

void SiiWriter::end_category() noexcept {
  if (category_start_ == 0) return;
  if ((at_ - category_start_) % 2 != 0) u8(0);
  const std::size_t words = (at_ - category_start_ - 4) / 2;
  store_le16(image_.data() + category_start_ + 2, static_cast<std::uint16_t>(words));
  category_start_ = 0;
}

void SiiWriter::u8(std::uint8_t v) noexcept {
  if (!room_for(1)) return;
  image_[at_++] = v;
}

void SiiWriter::u16(std::uint16_t v) noexcept {
  if (!room_for(2)) return;
  store_le16(image_.data() + at_, v);
  at_ += 2;
}

void SiiWriter::u32(std::uint32_t v) noexcept {
  if (!room_for(4)) return;
  store_le32(image_.data() + at_, v);
  at_ += 4;
}

void SiiWriter::zeros(std::size_t count) noexcept {
  if (!room_for(count)) return;
  std::memset(image_.data() + at_, 0, count);
  at_ += count;
}

void SiiWriter::string(const char* text) noexcept {
  const std::size_t length = std::strlen(text);
  if (length > 255) {
    if (status_.ok()) status_ = make_error(Errc::invalid_argument, "sii string longer than 255", static_cast<std::uint32_t>(length));
    return;
  }
  if (!room_for(1 + length)) return;
  image_[at_] = static_cast<std::uint8_t>(length);
  std::memcpy(image_.data() + at_ + 1, text, length);
  at_ += 1 + length;
}

Result<std::size_t> SiiWriter::finish() noexcept {
  end_category();
  if (!status_.ok()) return status_.error();
  store_le16(image_.data() + at_, ecat::sii::kCategoryEnd);
  at_ += 2;
  return at_;
}

void write_general(SiiWriter& w, const SiiGeneral& g) noexcept {
  w.u8(g.group_index);
  w.u8(g.image_index);
  w.u8(g.order_index);
  w.u8(g.name_index);
  w.u8(0);  // reserved
  w.u8(g.coe_details);
  w.u8(0);  // FoE details
  w.u8(0);  // EoE details
  w.u8(0);  // SoE channels
  w.u8(g.ds402_channels);
  w.u8(0);  // sysman class
  w.u8(g.flags);
  w.u16(static_cast<std::uint16_t>(g.current_on_ebus_ma));
  w.u8(g.group_index);  // group index again, for old masters
  w.u8(0);
  w.u16(g.physical_ports);
  w.u16(0);  // physical memory address
  w.zeros(ecat::sii::kGeneralSize - 20);
}

void write_sync_manager(SiiWriter& w, const ecat::sii::SyncManager& sm) noexcept {
  w.u16(sm.start_address);
  w.u16(sm.length);
  w.u8(sm.control);
  w.u8(sm.status);
  w.u8(sm.enable);
  w.u8(static_cast<std::uint8_t>(sm.type));
}

void write_dc_mode(SiiWriter& w, const ecat::sii::DcMode& mode) noexcept {
  w.u32(mode.cycle_time0);
  w.u32(mode.shift_time0);
  w.u32(mode.shift_time1);
  w.u16(static_cast<std::uint16_t>(mode.sync1_cycle_factor));
  w.u16(mode.assign_activate);
  w.u16(static_cast<std::uint16_t>(mode.sync0_cycle_factor));
  w.u8(mode.name_index);
  w.u8(mode.description_index);
  w.zeros(4);
}

}  // namespace rescue::drivers
