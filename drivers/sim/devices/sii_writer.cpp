#include "drivers/sim/devices/sii_writer.hpp"

#include <cstring>

#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

// The categories' writer: the image less the two bytes finish() keeps for the end marker.
ByteSpan categories_area(ByteSpan image) noexcept {
  return image.size() >= ecat::sii::kHeaderBytes + 2 ? image.first(image.size() - 2) : ByteSpan{};
}

}  // namespace

SiiWriter::SiiWriter(ByteSpan image, const SiiHeader& h) noexcept : image_(image), w_(categories_area(image)) {
  if (image.size() < ecat::sii::kHeaderBytes + 2) {
    status_ = make_error(Errc::capacity_exceeded, "sii image smaller than its header", 0, static_cast<std::uint32_t>(image.size()));
    return;
  }
  namespace sii = ecat::sii;
  std::memset(image.data(), 0xFF, image.size());
  std::memset(image.data(), 0, sii::kHeaderBytes);
  // The header's fields at their word addresses.
  const auto word16 = [&](std::uint16_t word, std::uint16_t v) { w_.u16_at(std::size_t{2} * word, v); };
  const auto word32 = [&](std::uint16_t word, std::uint32_t v) { w_.u32_at(std::size_t{2} * word, v); };
  word16(sii::kPdiControl, h.pdi_control);
  word16(sii::kPdiConfig, h.pdi_config);
  word16(sii::kSyncImpulseLength, h.sync_impulse_length);
  word16(sii::kPdiConfig2, h.pdi_config2);
  word16(sii::kStationAlias, h.station_alias);
  word16(sii::kConfigChecksum, sii::config_area_crc(image.data()));
  word32(sii::kVendorId, h.identity.vendor_id);
  word32(sii::kProductCode, h.identity.product_code);
  word32(sii::kRevision, h.identity.revision);
  word32(sii::kSerial, h.identity.serial_number);
  const sii::MailboxArea* areas[] = {&h.bootstrap_mailbox, &h.standard_mailbox};
  const std::uint16_t first_words[] = {sii::kBootRxMailboxOffset, sii::kStdRxMailboxOffset};
  for (std::size_t i = 0; i < 2; ++i) {
    const auto first = first_words[i];
    word16(first, areas[i]->receive_offset);
    word16(static_cast<std::uint16_t>(first + 1), areas[i]->receive_size);
    word16(static_cast<std::uint16_t>(first + 2), areas[i]->send_offset);
    word16(static_cast<std::uint16_t>(first + 3), areas[i]->send_size);
  }
  word16(sii::kMailboxProtocols, h.mailbox_protocols);
  word16(sii::kEepromSize, h.eeprom_size_word);
  word16(sii::kVersion, h.version);
  w_.skip(sii::kHeaderBytes);  // the categories follow the header
}

void SiiWriter::begin_category(std::uint16_t type) noexcept {
  if (category_start_ != 0) end_category();
  if (!w_.ok()) return;
  category_start_ = w_.size();
  w_.u16(type);
  w_.u16(0);
}

void SiiWriter::end_category() noexcept {
  if (category_start_ == 0) return;
  if ((w_.size() - category_start_) % 2 != 0) w_.u8(0);
  const std::size_t words = (w_.size() - category_start_ - 4) / 2;
  w_.u16_at(category_start_ + 2, static_cast<std::uint16_t>(words));
  category_start_ = 0;
}

void SiiWriter::u8(std::uint8_t v) noexcept { w_.u8(v); }
void SiiWriter::u16(std::uint16_t v) noexcept { w_.u16(v); }
void SiiWriter::u32(std::uint32_t v) noexcept { w_.u32(v); }
void SiiWriter::zeros(std::size_t count) noexcept { w_.zeros(count); }

void SiiWriter::string(const char* text) noexcept {
  const std::size_t length = std::strlen(text);
  if (length > 255) {
    if (status_.ok() && w_.ok()) status_ = make_error(Errc::invalid_argument, "sii string longer than 255", static_cast<std::uint32_t>(length));
    return;
  }
  w_.u8(static_cast<std::uint8_t>(length));
  w_.chars(text, length);
}

Result<std::size_t> SiiWriter::finish() noexcept {
  end_category();
  if (!status_.ok()) return status_.error();
  if (!w_.ok()) return make_error(Errc::capacity_exceeded, "sii image full", static_cast<std::uint32_t>(w_.size()));
  LeWriter end(image_);
  end.u16_at(w_.size(), ecat::sii::kCategoryEnd);
  return w_.size() + 2;
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
