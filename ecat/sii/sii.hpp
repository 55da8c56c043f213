// Slave Information Interface (SII, the slave's EEPROM; ETG.1000.6 section 5.4 and ETG.2010):
// the parser the master uses on images it reads from slaves, and the constants the simulator's
// image builder writes with.
//
// Layout (16-bit words, little-endian):
//   word 0x00..0x06  config area: PDI control, PDI config, sync impulse length, PDI config 2,
//                    configured station alias (0x04), reserved
//   word 0x07        low byte: CRC-8 over bytes 0..13 (poly 0x07, init 0xFF); high byte reserved
//   word 0x08..0x0F  identity: vendor id, product code, revision, serial number (u32 each)
//   word 0x14..0x17  bootstrap mailbox: receive offset/size, send offset/size
//   word 0x18..0x1B  standard mailbox: receive offset/size (master -> slave, SM0), send (SM1)
//   word 0x1C        supported mailbox protocols (bit mask, kMailbox*)
//   word 0x3E        EEPROM size: (value + 1) KiBit;  word 0x3F: SII version
//   word 0x40..      categories: u16 type, u16 size in words, data; type 0xFFFF ends the list
//
// Sii::parse takes untrusted bytes: every length and offset is checked against the image and
// against the category that holds it; a failure is an Error whose `what` names the field,
// detail0 the category type (or kConfigArea) and detail1 the byte offset in the image.
// The parsed Sii keeps a view of the image for its strings: the image must outlive it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/containers/fixed_vector.hpp"
#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat::sii {

// Word addresses of the fixed header, mailbox protocol bits and category types are in
// ecat/codec/registers.hpp (kVendorId, kStdRxMailboxOffset, kMailboxCoE, kCategoryGeneral, ...).
constexpr std::size_t kConfigAreaCrcBytes = 14;  // words 0..6
constexpr std::size_t kHeaderBytes = std::size_t{2} * kFirstCategory;  // 128

// Sizes of the fixed-size records inside categories (bytes).
constexpr std::size_t kGeneralSize = 32;
constexpr std::size_t kSyncManagerRecordSize = 8;
constexpr std::size_t kPdoHeaderSize = 8;
constexpr std::size_t kPdoEntrySize = 8;
constexpr std::size_t kDcRecordSize = 24;

// General category, CoE details byte.
constexpr std::uint8_t kCoeDetailSdo = 0x01;
constexpr std::uint8_t kCoeDetailSdoInfo = 0x02;
constexpr std::uint8_t kCoeDetailPdoAssign = 0x04;
constexpr std::uint8_t kCoeDetailPdoConfig = 0x08;
constexpr std::uint8_t kCoeDetailUploadAtStartup = 0x10;
constexpr std::uint8_t kCoeDetailSdoCompleteAccess = 0x20;

// General category, physical port nibbles (port 0 in bits 3..0).
constexpr std::uint8_t kPortNotUsed = 0x0;
constexpr std::uint8_t kPortMii = 0x1;
constexpr std::uint8_t kPortEbus = 0x3;

// SyncManager category, type byte.
enum class SyncManagerType : std::uint8_t { unused = 0, mailbox_out = 1, mailbox_in = 2, outputs = 3, inputs = 4 };
// FMMU category, one byte per FMMU (0xFF also means unused).
enum class FmmuUsage : std::uint8_t { unused = 0, outputs = 1, inputs = 2, sync_manager_status = 3 };

// Capacities of the parsed form. More than these in an image is refused (capacity_exceeded).
constexpr std::size_t kMaxStrings = 255;  // the count is one byte
constexpr std::size_t kMaxSyncManagers = 16;
constexpr std::size_t kMaxFmmus = 16;
constexpr std::size_t kMaxPdos = 64;          // per direction
constexpr std::size_t kMaxPdoEntries = 256;   // per direction, all PDOs together
constexpr std::size_t kMaxDcModes = 8;
constexpr std::uint32_t kConfigArea = 0xFFFFFFFFU;  // detail0 of errors in the fixed header

// CRC-8 of the config area as the ESC checks it on power-up (poly x^8+x^2+x+1, init 0xFF, no
// reflection, no final xor). `bytes` is the first 14 bytes of the image.
constexpr std::uint8_t config_area_crc(const std::uint8_t* bytes, std::size_t count = kConfigAreaCrcBytes) noexcept {
  std::uint8_t crc = 0xFF;
  for (std::size_t i = 0; i < count; ++i) {
    auto value = static_cast<unsigned>(crc ^ bytes[i]);
    for (int bit = 0; bit < 8; ++bit) value = (value & 0x80U) != 0 ? (value << 1U) ^ 0x07U : value << 1U;
    crc = static_cast<std::uint8_t>(value);
  }
  return crc;
}

struct Identity {
  std::uint32_t vendor_id{0};
  std::uint32_t product_code{0};
  std::uint32_t revision{0};
  std::uint32_t serial_number{0};
};

struct MailboxArea {
  std::uint16_t receive_offset{0};  // master -> slave (SM0)
  std::uint16_t receive_size{0};
  std::uint16_t send_offset{0};     // slave -> master (SM1)
  std::uint16_t send_size{0};
  bool present() const noexcept { return receive_size != 0 && send_size != 0; }
};

struct ConfigArea {
  std::uint16_t pdi_control{0};
  std::uint16_t pdi_config{0};
  std::uint16_t sync_impulse_length{0};
  std::uint16_t pdi_config2{0};
  std::uint16_t station_alias{0};
  std::uint8_t checksum{0};           // as stored (low byte of word 7)
  std::uint8_t computed_checksum{0};  // over words 0..6
  bool checksum_ok() const noexcept { return checksum == computed_checksum; }
};

struct General {
  std::uint8_t group_index{0};  // string indices: 0 = none
  std::uint8_t image_index{0};
  std::uint8_t order_index{0};
  std::uint8_t name_index{0};
  std::uint8_t coe_details{0};
  std::uint8_t foe_details{0};
  std::uint8_t eoe_details{0};
  std::uint8_t soe_channels{0};
  std::uint8_t ds402_channels{0};
  std::uint8_t sysman_class{0};
  std::uint8_t flags{0};
  std::int16_t current_on_ebus_ma{0};  // negative: the device feeds the E-bus
  std::uint16_t physical_ports{0};     // 4 nibbles, port 0 lowest
  std::uint16_t physical_memory_address{0};
};

struct SyncManager {
  std::uint16_t start_address{0};
  std::uint16_t length{0};
  std::uint8_t control{0};
  std::uint8_t status{0};
  std::uint8_t enable{0};
  SyncManagerType type{SyncManagerType::unused};
};

struct PdoEntry {
  std::uint16_t index{0};
  std::uint8_t subindex{0};
  std::uint8_t name_index{0};
  std::uint8_t data_type{0};
  std::uint8_t bit_length{0};
  std::uint16_t flags{0};
};

struct Pdo {
  std::uint16_t index{0};
  std::uint8_t sync_manager{0};  // 0xFF: not assigned by default
  std::uint8_t dc_sync{0};
  std::uint8_t name_index{0};
  std::uint16_t flags{0};
  std::uint16_t first_entry{0};  // into Sii::tx_entries / rx_entries
  std::uint8_t entry_count{0};
  std::uint32_t bit_length{0};   // sum of its entries
};

struct DcMode {
  std::uint32_t cycle_time0{0};
  std::uint32_t shift_time0{0};
  std::uint32_t shift_time1{0};
  std::int16_t sync1_cycle_factor{0};
  std::uint16_t assign_activate{0};  // written to 0x0980 by the master
  std::int16_t sync0_cycle_factor{0};
  std::uint8_t name_index{0};
  std::uint8_t description_index{0};
};

enum class ChecksumPolicy : std::uint8_t { require, ignore };

class Sii {
 public:
  // Parses a whole image (at least the 128-byte header). With ChecksumPolicy::require a config
  // area whose CRC does not match is refused (Errc::checksum), as the ESC itself would flag it.
  static Result<Sii> parse(ConstByteSpan image, ChecksumPolicy policy = ChecksumPolicy::require) noexcept;

  ConfigArea config{};
  Identity identity{};
  MailboxArea bootstrap_mailbox{};
  MailboxArea standard_mailbox{};
  std::uint16_t mailbox_protocols{0};
  std::uint32_t eeprom_size_bytes{0};  // from word 0x3E
  std::uint16_t version{0};

  bool has_general{false};
  General general{};
  FixedVector<SyncManager, kMaxSyncManagers> sync_managers{};
  FixedVector<FmmuUsage, kMaxFmmus> fmmus{};
  FixedVector<Pdo, kMaxPdos> tx_pdos{};
  FixedVector<PdoEntry, kMaxPdoEntries> tx_entries{};
  FixedVector<Pdo, kMaxPdos> rx_pdos{};
  FixedVector<PdoEntry, kMaxPdoEntries> rx_entries{};
  FixedVector<DcMode, kMaxDcModes> dc_modes{};
  std::size_t category_count{0};  // every category walked, known or not (the end marker excluded)
  std::size_t end_offset{0};      // byte offset just after the last category (or its end marker)

  bool supports(std::uint16_t protocol_bit) const noexcept { return (mailbox_protocols & protocol_bit) != 0; }

  // String `index` of the Strings category (1-based; 0 and unknown indices give "").
  std::string_view string(std::uint8_t index) const noexcept;
  std::size_t string_count() const noexcept { return strings_.size(); }
  std::string_view name() const noexcept { return string(general.name_index); }
  std::string_view order() const noexcept { return string(general.order_index); }
  std::string_view group() const noexcept { return string(general.group_index); }

  // Entries of one PDO (a view into tx_entries or rx_entries).
  Span<const PdoEntry> tx_entries_of(const Pdo& pdo) const noexcept;
  Span<const PdoEntry> rx_entries_of(const Pdo& pdo) const noexcept;
  // Total bits of the PDOs assigned by default to SyncManager `sm` (0xFF: none).
  std::uint32_t default_bits_of_sync_manager(std::uint8_t sm) const noexcept;

 private:
  struct StringRef {
    std::uint16_t offset{0};  // in the image
    std::uint8_t length{0};
  };
  friend struct SiiParser;
  ConstByteSpan image_{};
  FixedVector<StringRef, kMaxStrings> strings_{};
};

const char* to_string(SyncManagerType type) noexcept;

}  // namespace rescue::ecat::sii
