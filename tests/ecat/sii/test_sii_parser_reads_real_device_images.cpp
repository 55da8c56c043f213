// The SII parser against EEPROM images read from real devices (../shared/vectors/sii). The
// expected values were read from the bytes by hand and cross-checked against SOEM's SII reads
// in captures/soem-sdinfo-akd.pcapng (words 0x08..0x0D of the AKD: 0x6a, 0x00414b44, 2).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ecat/sii/sii.hpp"
#include "tests/support/shared_sii_images.hpp"

namespace rescue::ecat::sii {
namespace {

#define LOAD_OR_SKIP(var, name)                                                                     \
  const std::vector<std::uint8_t> var = test::read_shared_sii(name);                               \
  if (var.empty()) GTEST_SKIP() << "needs " RESCUE_SHARED_DIR "/vectors/sii/" name " (shared vectors absent)"

TEST(SiiRealImages, Ek1100CouplerHasBeckhoffIdentityAndNoMailbox) {
  LOAD_OR_SKIP(image, "ek1100.bin");
  auto r = Sii::parse(ConstByteSpan(image.data(), image.size()));
  ASSERT_TRUE(r.ok()) << r.error().what;
  const Sii& s = r.value();
  EXPECT_TRUE(s.config.checksum_ok());
  EXPECT_EQ(s.config.checksum, 0x46);
  EXPECT_EQ(s.identity.vendor_id, 0x00000002u);
  EXPECT_EQ(s.identity.product_code, 0x044c2c52u);
  EXPECT_EQ(s.identity.revision, 0x00120000u);
  EXPECT_EQ(s.config.station_alias, 0);
  EXPECT_FALSE(s.standard_mailbox.present());
  EXPECT_EQ(s.mailbox_protocols, 0);
  EXPECT_EQ(s.eeprom_size_bytes, 2048u);
  EXPECT_EQ(s.version, 1);
  ASSERT_TRUE(s.has_general);
  EXPECT_EQ(s.name(), "EK1100 EtherCAT-Koppler (2A E-Bus)");
  EXPECT_EQ(s.order(), "EK1100");
  EXPECT_EQ(s.group(), "SystemBk");
  EXPECT_EQ(s.string_count(), 4u);
  EXPECT_EQ(s.general.current_on_ebus_ma, -2000);  // the coupler feeds 2 A into the E-bus
  EXPECT_TRUE(s.sync_managers.empty());
  EXPECT_TRUE(s.tx_pdos.empty());
  EXPECT_TRUE(s.rx_pdos.empty());
  EXPECT_EQ(s.category_count, 2u);
}

TEST(SiiRealImages, AkdServoDriveHasKollmorgenIdentityMailboxAndPdos) {
  LOAD_OR_SKIP(image, "akd.bin");
  auto r = Sii::parse(ConstByteSpan(image.data(), image.size()));
  ASSERT_TRUE(r.ok()) << r.error().what;
  const Sii& s = r.value();
  EXPECT_EQ(s.config.checksum, 0x10);
  EXPECT_EQ(s.identity.vendor_id, 0x0000006au);
  EXPECT_EQ(s.identity.product_code, 0x00414b44u);  // "DKA" little-endian
  EXPECT_EQ(s.identity.revision, 0x00000002u);
  EXPECT_EQ(s.identity.serial_number, 0x99830093u);
  EXPECT_EQ(s.standard_mailbox.receive_offset, 0x1800);
  EXPECT_EQ(s.standard_mailbox.receive_size, 0x0400);
  EXPECT_EQ(s.standard_mailbox.send_offset, 0x1c00);
  EXPECT_EQ(s.standard_mailbox.send_size, 0x0400);
  EXPECT_EQ(s.bootstrap_mailbox.receive_offset, 0x1800);
  EXPECT_TRUE(s.supports(kMailboxCoE));
  EXPECT_TRUE(s.supports(kMailboxEoE));
  EXPECT_TRUE(s.supports(kMailboxFoE));
  EXPECT_FALSE(s.supports(kMailboxSoE));
  EXPECT_EQ(s.name(), "AKD EtherCAT Drive (CoE)");
  EXPECT_EQ(s.order(), "AKD");
  EXPECT_EQ(s.group(), "Drive");
  EXPECT_EQ(s.string_count(), 33u);
  EXPECT_EQ(s.general.coe_details, kCoeDetailSdo | kCoeDetailPdoAssign | kCoeDetailPdoConfig);
  EXPECT_EQ(s.general.ds402_channels, 1);
  EXPECT_EQ(s.general.physical_ports, 0x0011);  // two MII ports

  ASSERT_EQ(s.fmmus.size(), 3u);
  EXPECT_EQ(s.fmmus[0], FmmuUsage::outputs);
  EXPECT_EQ(s.fmmus[1], FmmuUsage::inputs);
  EXPECT_EQ(s.fmmus[2], FmmuUsage::sync_manager_status);

  ASSERT_EQ(s.sync_managers.size(), 4u);
  EXPECT_EQ(s.sync_managers[0].start_address, 0x1800);
  EXPECT_EQ(s.sync_managers[0].control, 0x26);
  EXPECT_EQ(s.sync_managers[0].type, SyncManagerType::mailbox_out);
  EXPECT_EQ(s.sync_managers[1].type, SyncManagerType::mailbox_in);
  EXPECT_EQ(s.sync_managers[2].start_address, 0x1100);
  EXPECT_EQ(s.sync_managers[2].type, SyncManagerType::outputs);
  EXPECT_EQ(s.sync_managers[3].start_address, 0x1140);
  EXPECT_EQ(s.sync_managers[3].type, SyncManagerType::inputs);

  ASSERT_EQ(s.tx_pdos.size(), 12u);
  EXPECT_EQ(s.tx_pdos[0].index, 0x1a00);
  const Pdo& tx_default = s.tx_pdos[4];  // 0x1B01 is the one assigned to SM3
  EXPECT_EQ(tx_default.index, 0x1b01);
  EXPECT_EQ(tx_default.sync_manager, 3);
  ASSERT_EQ(tx_default.entry_count, 2);
  EXPECT_EQ(s.tx_entries_of(tx_default)[0].index, 0x6063);
  EXPECT_EQ(s.tx_entries_of(tx_default)[0].bit_length, 32);
  EXPECT_EQ(s.tx_entries_of(tx_default)[1].index, 0x6041);
  EXPECT_EQ(s.string(s.tx_entries_of(tx_default)[1].name_index), "Statusword");
  EXPECT_EQ(s.string(tx_default.name_index), "Inputs");
  EXPECT_EQ(s.default_bits_of_sync_manager(3), 48u);

  ASSERT_EQ(s.rx_pdos.size(), 12u);
  const Pdo& rx_default = s.rx_pdos[4];
  EXPECT_EQ(rx_default.index, 0x1701);
  EXPECT_EQ(rx_default.sync_manager, 2);
  EXPECT_EQ(s.rx_entries_of(rx_default)[0].index, 0x60c1);
  EXPECT_EQ(s.rx_entries_of(rx_default)[0].subindex, 1);
  EXPECT_EQ(s.default_bits_of_sync_manager(2), 48u);

  ASSERT_EQ(s.dc_modes.size(), 2u);
  EXPECT_EQ(s.dc_modes[0].assign_activate, 0x0300);
  EXPECT_EQ(s.dc_modes[0].sync0_cycle_factor, 1);
  EXPECT_EQ(s.string(s.dc_modes[0].name_index), "DcSync");
  EXPECT_EQ(s.dc_modes[1].assign_activate, 0x0000);
  EXPECT_EQ(s.string(s.dc_modes[1].name_index), "DcOff");
}

TEST(SiiRealImages, El2828TerminalHasOutputPdosOnSm0AndSkipsVendorCategory) {
  LOAD_OR_SKIP(image, "el2828.bin");
  auto r = Sii::parse(ConstByteSpan(image.data(), image.size()));
  ASSERT_TRUE(r.ok()) << r.error().what;
  const Sii& s = r.value();
  EXPECT_EQ(s.config.checksum, 0xe2);
  EXPECT_EQ(s.identity.vendor_id, 0x00000002u);
  EXPECT_EQ(s.identity.product_code, 0x0b0c3052u);
  EXPECT_EQ(s.identity.revision, 0x00110000u);
  EXPECT_EQ(s.name(), "EL2828 8K. Dig. Ausgang 24V, 2A");
  EXPECT_EQ(s.order(), "EL2828");
  EXPECT_FALSE(s.standard_mailbox.present());
  ASSERT_EQ(s.fmmus.size(), 1u);  // 01 then the 0xFF pad byte
  EXPECT_EQ(s.fmmus[0], FmmuUsage::outputs);
  ASSERT_EQ(s.sync_managers.size(), 1u);
  EXPECT_EQ(s.sync_managers[0].start_address, 0x0f00);
  EXPECT_EQ(s.sync_managers[0].control, 0x44);
  EXPECT_EQ(s.sync_managers[0].type, SyncManagerType::outputs);
  EXPECT_TRUE(s.tx_pdos.empty());
  ASSERT_EQ(s.rx_pdos.size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(s.rx_pdos[i].index, 0x1600 + i);
    EXPECT_EQ(s.rx_pdos[i].sync_manager, 0);
    ASSERT_EQ(s.rx_pdos[i].entry_count, 1);
    EXPECT_EQ(s.rx_entries_of(s.rx_pdos[i])[0].index, 0x7000 + 0x10 * i);
    EXPECT_EQ(s.rx_entries_of(s.rx_pdos[i])[0].bit_length, 1);
    EXPECT_EQ(s.string(s.rx_pdos[i].name_index), "Channel " + std::to_string(i + 1));
  }
  EXPECT_EQ(s.default_bits_of_sync_manager(0), 8u);
  EXPECT_EQ(s.category_count, 7u);  // including the vendor category 3 and the sync unit 43
}

}  // namespace
}  // namespace rescue::ecat::sii
