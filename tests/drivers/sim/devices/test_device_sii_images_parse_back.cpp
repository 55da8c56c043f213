// The SII images our two device types carry parse back with the master's parser (ecat/sii/sii.hpp):
// identity, unique serials, commissioned aliases, the config-area CRC, the drive's mailbox and
// SyncManagers, and PDO categories equal to the process-data layout of drivers/joint/joint_drive_pdo.hpp.
#include <gtest/gtest.h>

#include <set>

#include "core/robot/robot.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "drivers/sim/devices/joint_drive_sii.hpp"
#include "drivers/sim/devices/junction_device.hpp"
#include "ecat/sii/sii.hpp"

namespace rescue::drivers {
namespace {

using ecat::sii::Sii;

template <std::size_t N>
void expect_pdo_matches(const Sii& s, const ecat::sii::Pdo& pdo, Span<const ecat::sii::PdoEntry> entries,
                        const std::array<PdoMappingEntry, N>& mapping) {
  ASSERT_EQ(pdo.entry_count, N);
  for (std::size_t i = 0; i < N; ++i) {
    EXPECT_EQ(entries[i].index, mapping[i].index) << i;
    EXPECT_EQ(entries[i].subindex, mapping[i].subindex) << i;
    EXPECT_EQ(entries[i].bit_length, mapping[i].bit_length) << i;
    EXPECT_EQ(entries[i].data_type, mapping[i].data_type) << i;
    EXPECT_EQ(s.string(entries[i].name_index), mapping[i].name) << i;
  }
}

TEST(JointDriveSii, EveryDriveSlotParsesBackWithItsIdentityAndLayout) {
  std::set<std::uint32_t> serials;
  for (std::size_t position = 0; position < kSlaveCount; ++position) {
    if (kSlaves[position].kind != SlaveKind::joint_drive) continue;
    auto image = build_joint_drive_sii(position);
    ASSERT_TRUE(image.ok()) << image.error().what;
    auto parsed = Sii::parse(ConstByteSpan(image.value()));
    ASSERT_TRUE(parsed.ok()) << parsed.error().what;
    const Sii& s = parsed.value();
    EXPECT_TRUE(s.config.checksum_ok());
    EXPECT_EQ(s.identity.vendor_id, kRescueVendorId);
    EXPECT_EQ(s.identity.product_code, kJointDriveIdentity.product_code);
    EXPECT_EQ(s.identity.revision, kJointDriveIdentity.revision);
    EXPECT_EQ(s.identity.serial_number, serial_number_of(position));
    EXPECT_TRUE(serials.insert(s.identity.serial_number).second) << "serial repeated at " << position;
    EXPECT_EQ(s.config.station_alias, kSlaves[position].station_address);
    EXPECT_EQ(s.name(), kJointDriveIdentity.name);
    EXPECT_EQ(s.order(), kJointDriveIdentity.name);
    EXPECT_EQ(s.group(), "Drives");
    EXPECT_EQ(s.eeprom_size_bytes, kSiiImageBytes);
  }
  EXPECT_EQ(serials.size(), kJointCount);
}

TEST(JointDriveSii, MailboxSyncManagersFmmusPdosAndDcModes) {
  const std::size_t position = slave_position_of_joint(joint_index_by_name("l_elbow"));
  auto image = build_joint_drive_sii(position);
  ASSERT_TRUE(image.ok());
  auto parsed = Sii::parse(ConstByteSpan(image.value()));
  ASSERT_TRUE(parsed.ok());
  const Sii& s = parsed.value();

  EXPECT_EQ(s.mailbox_protocols, ecat::sii::kMailboxCoE);
  EXPECT_EQ(s.standard_mailbox.receive_offset, kJointMailboxOutStart);
  EXPECT_EQ(s.standard_mailbox.receive_size, kJointMailboxSize);
  EXPECT_EQ(s.standard_mailbox.send_offset, kJointMailboxInStart);
  EXPECT_EQ(s.standard_mailbox.send_size, kJointMailboxSize);
  EXPECT_FALSE(s.bootstrap_mailbox.present());
  EXPECT_EQ(s.general.coe_details, 0x2F);  // SDO, SDO information, PDO assign, PDO config, complete access
  EXPECT_EQ(s.general.ds402_channels, 1);
  EXPECT_EQ(s.general.physical_ports, 0x0011);

  ASSERT_EQ(s.fmmus.size(), 3u);
  EXPECT_EQ(s.fmmus[0], ecat::sii::FmmuUsage::outputs);
  EXPECT_EQ(s.fmmus[1], ecat::sii::FmmuUsage::inputs);
  EXPECT_EQ(s.fmmus[2], ecat::sii::FmmuUsage::sync_manager_status);

  ASSERT_EQ(s.sync_managers.size(), 4u);
  const std::uint16_t starts[] = {kJointMailboxOutStart, kJointMailboxInStart, kJointOutputsStart, kJointInputsStart};
  const std::uint16_t lengths[] = {kJointMailboxSize, kJointMailboxSize, kJointOutputBytes, kJointInputBytes};
  const std::uint8_t controls[] = {0x26, 0x22, 0x64, 0x20};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(s.sync_managers[i].start_address, starts[i]) << i;
    EXPECT_EQ(s.sync_managers[i].length, lengths[i]) << i;
    EXPECT_EQ(s.sync_managers[i].control, controls[i]) << i;
    EXPECT_EQ(s.sync_managers[i].enable, 1) << i;
    EXPECT_EQ(static_cast<int>(s.sync_managers[i].type), static_cast<int>(i + 1)) << i;
  }

  ASSERT_EQ(s.tx_pdos.size(), 1u);
  EXPECT_EQ(s.tx_pdos[0].index, kJointTxPdoIndex);
  EXPECT_EQ(s.tx_pdos[0].sync_manager, kJointInputsSyncManager);
  EXPECT_EQ(s.string(s.tx_pdos[0].name_index), "Inputs");
  expect_pdo_matches(s, s.tx_pdos[0], s.tx_entries_of(s.tx_pdos[0]), kJointTxMapping);
  ASSERT_EQ(s.rx_pdos.size(), 1u);
  EXPECT_EQ(s.rx_pdos[0].index, kJointRxPdoIndex);
  EXPECT_EQ(s.rx_pdos[0].sync_manager, kJointOutputsSyncManager);
  expect_pdo_matches(s, s.rx_pdos[0], s.rx_entries_of(s.rx_pdos[0]), kJointRxMapping);
  EXPECT_EQ(s.default_bits_of_sync_manager(kJointOutputsSyncManager), 8 * kJointOutputBytes);
  EXPECT_EQ(s.default_bits_of_sync_manager(kJointInputsSyncManager), 8 * kJointInputBytes);

  ASSERT_EQ(s.dc_modes.size(), 2u);
  EXPECT_EQ(s.dc_modes[0].assign_activate, 0x0300);
  EXPECT_EQ(s.dc_modes[0].sync0_cycle_factor, 1);
  EXPECT_EQ(s.string(s.dc_modes[0].name_index), "DC-Synchron");
  EXPECT_EQ(s.dc_modes[1].assign_activate, 0x0000);
  EXPECT_EQ(s.string(s.dc_modes[1].name_index), "SM-Synchron");
  // Past the end marker the EEPROM is erased, as on real devices.
  EXPECT_EQ(image.value()[s.end_offset], 0xFF);
  EXPECT_LT(s.end_offset, kSiiImageBytes);
}

TEST(JunctionSii, BothJunctionsParseBackWithoutMailboxOrProcessData) {
  for (std::size_t position = 0; position < kSlaveCount; ++position) {
    if (kSlaves[position].kind != SlaveKind::junction) continue;
    const JunctionDevice junction(position);
    auto parsed = Sii::parse(junction.sii_image());
    ASSERT_TRUE(parsed.ok()) << parsed.error().what;
    const Sii& s = parsed.value();
    EXPECT_EQ(s.identity.vendor_id, kRescueVendorId);
    EXPECT_EQ(s.identity.product_code, kJunctionIdentity.product_code);
    EXPECT_EQ(s.identity.serial_number, serial_number_of(position));
    EXPECT_EQ(s.config.station_alias, kSlaves[position].station_address);
    EXPECT_EQ(s.name(), kJunctionIdentity.name);
    EXPECT_FALSE(s.standard_mailbox.present());
    EXPECT_EQ(s.mailbox_protocols, 0);
    EXPECT_TRUE(s.sync_managers.empty());
    EXPECT_TRUE(s.tx_pdos.empty());
    EXPECT_TRUE(s.rx_pdos.empty());
  }
}

}  // namespace
}  // namespace rescue::drivers
