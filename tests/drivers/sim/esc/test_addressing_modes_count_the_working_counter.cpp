// Each addressing mode reaches the slaves ETG.1000.4 says it reaches, and each command adds to the
// working counter what real ESCs add, on the robot's 23-slave segment.
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

class Addressing : public ::testing::Test {
 protected:
  void SetUp() override { rig = Rig::robot(); }
  std::unique_ptr<Rig> rig;
};

TEST_F(Addressing, BroadcastReadIsAnsweredByEverySlaveAndOrsTheData) {
  const auto r = rig->read(Command::BRD, 0, reg::kType, 2);
  EXPECT_EQ(r.wkc, kSlaveCount);
  EXPECT_EQ(r.adp, kSlaveCount);  // every slave incremented ADP
  // Junctions are type 0x11, joints 0xC0: the master sees the OR.
  EXPECT_EQ(r.data[0], 0x11 | 0xC0);
}

TEST_F(Addressing, AutoIncrementAddressesTheSlaveWhereAdpReachesZero) {
  for (std::uint16_t p = 0; p < kSlaveCount; ++p) {
    const auto r = rig->read(Command::APRD, ecat::position_adp(p), reg::kPortDescriptor, 1);
    EXPECT_EQ(r.wkc, 1) << p;
    EXPECT_EQ(r.adp, static_cast<std::uint16_t>(ecat::position_adp(p) + kSlaveCount)) << p;
    EXPECT_EQ(r.data[0], kSlaves[p].kind == SlaveKind::junction ? 0xFF : 0x0F) << p;  // 4 or 2 MII ports
  }
  EXPECT_EQ(rig->read(Command::APRD, ecat::position_adp(kSlaveCount), reg::kType, 1).wkc, 0);  // nobody there
}

TEST_F(Addressing, ConfiguredAddressReachesOneSlaveAndAliasOnlyWhenEnabled) {
  rig->assign_station_addresses();
  for (std::uint16_t p = 0; p < kSlaveCount; ++p) {
    EXPECT_EQ(rig->read(Command::FPRD, static_cast<std::uint16_t>(0x1000 + p), reg::kStationAddress, 2).wkc, 1) << p;
  }
  // The joints' SII carries an alias (their designed station address, written at commissioning);
  // move the station addresses away so alias and address differ.
  for (std::uint16_t p = 0; p < kSlaveCount; ++p) {
    EXPECT_EQ(rig->write16(static_cast<std::uint16_t>(0x1000 + p), reg::kStationAddress, static_cast<std::uint16_t>(0x2000 + p)), 1);
  }
  EXPECT_EQ(rig->read16(0x2005, reg::kStationAlias), 0x1005);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1005, reg::kType, 1).wkc, 0);  // alias not enabled yet
  // DL control bit 24 enables the alias for configured-address commands.
  EXPECT_EQ(rig->write(Command::FPWR, 0x2005, reg::kDlControl, le32(0x01070001)).wkc, 1);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1005, reg::kType, 1).wkc, 1);
  EXPECT_EQ(rig->read(Command::FPRD, 0x2005, reg::kType, 1).wkc, 1);
}

TEST_F(Addressing, WritesCountOncePerSlaveAndReadWriteCountsThree) {
  rig->assign_station_addresses();
  EXPECT_EQ(rig->write(Command::BWR, 0, reg::kEcatEventMask, le16(0)).wkc, kSlaveCount);
  EXPECT_EQ(rig->write(Command::APWR, ecat::position_adp(4), 0x0F80, {1, 2}).wkc, 1);  // user RAM
  // Read-write: the frame leaves with the old content, the memory keeps the new one: 1 + 2.
  const auto rw = rig->write(Command::FPRW, 0x1004, 0x0F80, {7, 8});
  EXPECT_EQ(rw.wkc, 3);
  EXPECT_EQ(rw.data, (std::vector<std::uint8_t>{1, 2}));
  EXPECT_EQ(rig->read(Command::APRD, ecat::position_adp(4), 0x0F80, 2).data, (std::vector<std::uint8_t>{7, 8}));
  EXPECT_EQ(rig->write(Command::APRW, ecat::position_adp(4), 0x0F80, {9, 9}).wkc, 3);
  EXPECT_EQ(rig->write(Command::BRW, 0, 0x0F80, {0, 0}).wkc, 3 * kSlaveCount);
}

TEST_F(Addressing, ReadMultipleWriteReadsAtTheAddressedSlaveAndWritesAtAllOthers) {
  rig->assign_station_addresses();
  // User RAM 0x0F80: every slave has it, readable and writable.
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, 0x0F80, {0xAB, 0xCD}).wkc, 1);
  const auto armw = rig->write(Command::ARMW, ecat::position_adp(0), 0x0F80, {0, 0});
  EXPECT_EQ(armw.wkc, kSlaveCount);  // 1 read + 22 writes
  EXPECT_EQ(armw.data, (std::vector<std::uint8_t>{0xAB, 0xCD}));
  EXPECT_EQ(rig->read(Command::FPRD, 0x1016, 0x0F80, 2).data, (std::vector<std::uint8_t>{0xAB, 0xCD}));
  const auto frmw = rig->write(Command::FRMW, 0x1007, 0x0F80, {0x55, 0x55});
  EXPECT_EQ(frmw.wkc, kSlaveCount);
  EXPECT_EQ(frmw.data, (std::vector<std::uint8_t>{0xAB, 0xCD}));
}

TEST_F(Addressing, RegistersAnEscDoesNotHaveAreNotCounted) {
  // As real chains show: FMMU 3 exists on the junctions (8 FMMUs), not on the joints (3 FMMUs).
  EXPECT_EQ(rig->write(Command::BWR, 0, reg::fmmu(0), std::vector<std::uint8_t>(16, 0)).wkc, kSlaveCount);
  EXPECT_EQ(rig->write(Command::BWR, 0, reg::fmmu(3), std::vector<std::uint8_t>(16, 0)).wkc, kJunctionCount);
  EXPECT_EQ(rig->write(Command::BWR, 0, reg::sync_manager(4), std::vector<std::uint8_t>(8, 0)).wkc, kJunctionCount);
  EXPECT_EQ(rig->read(Command::BRD, 0, 0x0F00, 4).wkc, 0);  // digital I/O: not implemented
  EXPECT_EQ(rig->read(Command::BRD, 0, 0x2800, 4).wkc, kJunctionCount);  // RAM beyond the joints' 4 KiB
  EXPECT_EQ(rig->read(Command::BRD, 0, 0x3000, 4).wkc, 0);                // beyond every RAM
  // Read-only registers: writes are refused and not counted (0x092C, ESC information).
  EXPECT_EQ(rig->write(Command::BWR, 0, reg::kDcSystemTimeDifference, le32(0)).wkc, 0);
  EXPECT_EQ(rig->write(Command::BWR, 0, reg::kType, {0}).wkc, 0);
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).data[0], 0x11 | 0xC0);
  // A block with existing and reserved bytes counts (AL status 0x0130 + reserved + code).
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kAlStatus, 6).wkc, kSlaveCount);
}

TEST_F(Addressing, NopReachesNobody) {
  const auto r = rig->exchange(Command::NOP, ecat::make_address(0, 0x0F80), {1, 2});
  EXPECT_TRUE(r.returned);
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.adp, 0);
}

class Logical : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = Rig::single();
    rig->assign_station_addresses();
  }
  std::unique_ptr<Rig> rig;
};

TEST_F(Logical, SeparateReadAndWriteFmmusCountOneTwoAndThree) {
  // Plain RAM (no SyncManager): outputs FMMU at logical 0x10000, inputs FMMU at 0x10010.
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, reg::fmmu(0), fmmu_config(0x10000, 4, 0x1400, 2)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, reg::fmmu(1), fmmu_config(0x10010, 4, 0x1500, 1)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, 0x1500, {1, 2, 3, 4}).wkc, 1);

  EXPECT_EQ(rig->exchange(Command::LWR, 0x10000, {9, 8, 7, 6}).wkc, 1);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1000, 0x1400, 4).data, (std::vector<std::uint8_t>{9, 8, 7, 6}));
  const auto lrd = rig->exchange(Command::LRD, 0x10010, {0, 0, 0, 0});
  EXPECT_EQ(lrd.wkc, 1);
  EXPECT_EQ(lrd.data, (std::vector<std::uint8_t>{1, 2, 3, 4}));
  // LRD of an area only a write FMMU maps, LWR of one only a read FMMU maps: nothing.
  EXPECT_EQ(rig->exchange(Command::LRD, 0x10000, {0, 0, 0, 0}).wkc, 0);
  EXPECT_EQ(rig->exchange(Command::LWR, 0x10010, {0, 0, 0, 0}).wkc, 0);
  // LRW over both: +2 for the write, +1 for the read.
  const auto lrw = rig->exchange(Command::LRW, 0x10000, std::vector<std::uint8_t>(0x14, 5));
  EXPECT_EQ(lrw.wkc, 3);
  EXPECT_EQ(std::vector<std::uint8_t>(lrw.data.begin() + 0x10, lrw.data.end()), (std::vector<std::uint8_t>{1, 2, 3, 4}));
  EXPECT_EQ(lrw.data[0], 5);  // bytes only written stay as the master sent them
  EXPECT_EQ(rig->exchange(Command::LRW, 0x10000, {1, 1, 1, 1}).wkc, 2);  // write part only
  EXPECT_EQ(rig->exchange(Command::LRW, 0x10010, {1, 1, 1, 1}).wkc, 1);  // read part only
  EXPECT_EQ(rig->exchange(Command::LRW, 0x20000, {1, 1, 1, 1}).wkc, 0);  // not mapped
}

TEST_F(Logical, OverlappingReadAndWriteFmmusExchangeTheSameBytes) {
  // Outputs and inputs on the same logical bytes (a master's "overlapping" process image).
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, reg::fmmu(0), fmmu_config(0x3000, 2, 0x1400, 2)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, reg::fmmu(1), fmmu_config(0x3000, 2, 0x1500, 1)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, 0x1500, {0x11, 0x22}).wkc, 1);
  const auto lrw = rig->exchange(Command::LRW, 0x3000, {0xA1, 0xA2});
  EXPECT_EQ(lrw.wkc, 3);
  EXPECT_EQ(lrw.data, (std::vector<std::uint8_t>{0x11, 0x22}));  // inputs came back
  EXPECT_EQ(rig->read(Command::FPRD, 0x1000, 0x1400, 2).data, (std::vector<std::uint8_t>{0xA1, 0xA2}));  // outputs arrived
}

TEST_F(Logical, BitwiseFmmuMapsOnlyItsBits) {
  // Logical bits 0x4000.2 .. 0x4000.5 <-> physical 0x1600.4 .. 0x1601.0 (4 bits, crossing a byte).
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, reg::fmmu(0), fmmu_config(0x4000, 1, 0x1600, 2, 2, 5, 5)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, reg::fmmu(1), fmmu_config(0x4000, 1, 0x1700, 1, 2, 5, 5)).wkc, 1);
  EXPECT_EQ(rig->exchange(Command::LWR, 0x4000, {0xFF}).wkc, 1);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1000, 0x1600, 2).data, (std::vector<std::uint8_t>{0xE0, 0x01}));
  EXPECT_EQ(rig->write(Command::FPWR, 0x1000, 0x1700, {0xA0, 0x00}).wkc, 1);  // bits 5 and 7 set
  const auto lrd = rig->exchange(Command::LRD, 0x4000, {0x00});
  EXPECT_EQ(lrd.wkc, 1);
  // Physical bits 5..8 = 1, 0, 1, 0 -> logical bits 2..5 = 1, 0, 1, 0; other bits untouched.
  EXPECT_EQ(lrd.data[0], 0x14);
  const auto lrd_keep = rig->exchange(Command::LRD, 0x4000, {0xC3});
  EXPECT_EQ(lrd_keep.data[0], (0xC3 & ~0x3C) | 0x14);
}

}  // namespace
}  // namespace rescue::drivers::testing
