#include "drivers/sim/devices/joint_drive_sii.hpp"

#include "drivers/joint/device_identity.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "drivers/sim/devices/sii_writer.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

namespace sii = ecat::sii;

// String indices (1-based) in the order the Strings category lists them.
enum StringIndex : std::uint8_t {
  kStrName = 1,
  kStrGroup,
  kStrInputs,
  kStrOutputs,
  kStrDcSync,
  kStrSmSync,
  kStrFirstTxEntry,
  kStrFirstRxEntry = kStrFirstTxEntry + kJointTxMapping.size(),
};

template <std::size_t N>
void write_pdo(SiiWriter& w, std::uint16_t index, std::uint8_t sm, std::uint8_t name,
               const std::array<PdoMappingEntry, N>& entries, std::uint8_t first_entry_name) noexcept {
  w.u16(index);
  w.u8(static_cast<std::uint8_t>(N));
  w.u8(sm);
  w.u8(0);  // synchronisation
  w.u8(name);
  w.u16(0);  // flags
  for (std::size_t i = 0; i < N; ++i) {
    w.u16(entries[i].index);
    w.u8(entries[i].subindex);
    w.u8(static_cast<std::uint8_t>(first_entry_name + i));
    w.u8(static_cast<std::uint8_t>(entries[i].data_type));
    w.u8(entries[i].bit_length);
    w.u16(0);  // flags
  }
}

}  // namespace

Result<SiiImage> build_joint_drive_sii(std::size_t position) noexcept {
  SiiImage image{};
  SiiHeader h;
  h.pdi_control = 0x0005;  // SPI PDI: the drive's microcontroller talks to its ESC over SPI
  h.station_alias = position < kSlaveCount ? station_alias_of(position) : 0;
  h.identity = {kJointDriveIdentity.vendor_id, kJointDriveIdentity.product_code, kJointDriveIdentity.revision,
                serial_number_of(position)};
  h.standard_mailbox = {kJointMailboxOutStart, kJointMailboxSize, kJointMailboxInStart, kJointMailboxSize};
  h.mailbox_protocols = sii::kMailboxCoE;
  SiiWriter w(ByteSpan(image), h);

  w.begin_category(sii::kCategoryStrings);
  w.u8(static_cast<std::uint8_t>(kStrFirstRxEntry - 1 + kJointRxMapping.size()));
  w.string(kJointDriveIdentity.name);
  w.string("Drives");
  w.string("Inputs");
  w.string("Outputs");
  w.string("DC-Synchron");
  w.string("SM-Synchron");
  for (const PdoMappingEntry& e : kJointTxMapping) w.string(e.name);
  for (const PdoMappingEntry& e : kJointRxMapping) w.string(e.name);

  w.begin_category(sii::kCategoryGeneral);
  SiiGeneral g;
  g.group_index = kStrGroup;
  g.order_index = kStrName;
  g.name_index = kStrName;
  g.coe_details = sii::kCoeDetailSdo | sii::kCoeDetailSdoInfo | sii::kCoeDetailPdoAssign | sii::kCoeDetailPdoConfig |
                  sii::kCoeDetailSdoCompleteAccess;
  g.ds402_channels = 1;
  g.physical_ports = sii::kPortMii | (sii::kPortMii << 4U);
  write_general(w, g);

  w.begin_category(sii::kCategoryFmmu);
  w.u8(static_cast<std::uint8_t>(sii::FmmuUsage::outputs));
  w.u8(static_cast<std::uint8_t>(sii::FmmuUsage::inputs));
  w.u8(static_cast<std::uint8_t>(sii::FmmuUsage::sync_manager_status));
  w.u8(0xFF);  // pad to a word, as real images do

  w.begin_category(sii::kCategorySyncManager);
  write_sync_manager(w, {kJointMailboxOutStart, kJointMailboxSize, kSmControlMailboxOut, 0, 1, sii::SyncManagerType::mailbox_out});
  write_sync_manager(w, {kJointMailboxInStart, kJointMailboxSize, kSmControlMailboxIn, 0, 1, sii::SyncManagerType::mailbox_in});
  write_sync_manager(w, {kJointOutputsStart, static_cast<std::uint16_t>(kJointOutputBytes), kSmControlOutputs, 0, 1,
                         sii::SyncManagerType::outputs});
  write_sync_manager(w, {kJointInputsStart, static_cast<std::uint16_t>(kJointInputBytes), kSmControlInputs, 0, 1,
                         sii::SyncManagerType::inputs});

  w.begin_category(sii::kCategoryTxPdo);
  write_pdo(w, kJointTxPdoIndex, kJointInputsSyncManager, kStrInputs, kJointTxMapping, kStrFirstTxEntry);
  w.begin_category(sii::kCategoryRxPdo);
  write_pdo(w, kJointRxPdoIndex, kJointOutputsSyncManager, kStrOutputs, kJointRxMapping, kStrFirstRxEntry);

  w.begin_category(sii::kCategoryDc);
  sii::DcMode dc_sync{};
  dc_sync.assign_activate = kDcAssignActivateSync0;
  dc_sync.sync0_cycle_factor = 1;
  dc_sync.name_index = kStrDcSync;
  write_dc_mode(w, dc_sync);
  sii::DcMode sm_sync{};
  sm_sync.name_index = kStrSmSync;
  write_dc_mode(w, sm_sync);

  auto used = w.finish();
  if (!used.ok()) return used.error();
  return image;
}

}  // namespace rescue::drivers
