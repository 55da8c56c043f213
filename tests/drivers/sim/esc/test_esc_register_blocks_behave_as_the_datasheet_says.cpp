// Register blocks outside the big units: ESC information, station address and alias, DL status
// per port, ECAT events and the datagram IRQ field, error and lost-link counters, watchdogs, user
// RAM, and the PDI-related bits (PDI operational, PDI watchdog) on joints and junctions.
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

class Registers : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = Rig::robot();
    rig->assign_station_addresses();
  }
  std::unique_ptr<Rig> rig;
};

TEST_F(Registers, EscInformationDescribesTheSilicon) {
  const auto junction = rig->read(Command::FPRD, 0x1000, reg::kType, 10).data;
  EXPECT_EQ(junction, (std::vector<std::uint8_t>{0x11, 0x00, 0x03, 0x00, 8, 8, 8, 0xFF, 0xCC, 0x01}));
  const auto joint = rig->read(Command::FPRD, 0x1002, reg::kType, 10).data;
  EXPECT_EQ(joint, (std::vector<std::uint8_t>{0xC0, 0x02, 0x01, 0x00, 3, 4, 4, 0x0F, 0xCC, 0x01}));
}

TEST_F(Registers, StationAddressIsWritableAndTheAliasComesFromTheSii) {
  EXPECT_EQ(rig->read16(0x1003, reg::kStationAddress), 0x1003);
  EXPECT_EQ(rig->read16(0x1003, reg::kStationAlias), 0x1003);  // commissioned alias (SII word 4)
  EXPECT_EQ(rig->write16(0x1003, reg::kStationAlias, 0x7777), 0);  // read-only for the master
  EXPECT_EQ(rig->read16(0x1003, reg::kStationAlias), 0x1003);
  EXPECT_EQ(rig->read16(0x1000, reg::kStationAlias), 0x1000);  // the junctions are commissioned too
}

TEST_F(Registers, DlStatusShowsLinkLoopAndCommunicationPerPort) {
  // junction_a: ports 0, 1, 2, 3 all cabled and open.
  const std::uint16_t a = rig->read16(0x1000, reg::kDlStatus);
  for (unsigned port = 0; port < 4; ++port) {
    EXPECT_NE(a & reg::dl_status_link(port), 0) << port;
    EXPECT_NE(a & reg::dl_status_communication(port), 0) << port;
    EXPECT_EQ(a & reg::dl_status_loop_closed(port), 0) << port;
  }
  EXPECT_EQ(a & reg::kDlStatusPdiOperational, reg::kDlStatusPdiOperational);  // EEPROM loaded
  EXPECT_EQ(a & reg::kDlStatusPdiWatchdog, 0);  // no application behind a junction
  // junction_b: port 3 unused (closed, no link).
  const std::uint16_t b = rig->read16(0x1001, reg::kDlStatus);
  EXPECT_EQ(b & reg::dl_status_link(3), 0);
  EXPECT_NE(b & reg::dl_status_loop_closed(3), 0);
  // Last joint of the torso: port 1 closed, ports 2 and 3 do not exist (closed).
  const std::uint16_t neck_tilt = rig->read16(0x100F, reg::kDlStatus);
  EXPECT_EQ(neck_tilt, reg::kDlStatusPdiOperational | reg::kDlStatusPdiWatchdog | reg::dl_status_link(0) |
                           reg::dl_status_communication(0) | reg::dl_status_loop_closed(1) |
                           reg::dl_status_loop_closed(2) | reg::dl_status_loop_closed(3));
}

TEST_F(Registers, EventsReachTheIrqFieldOnlyThroughTheMask) {
  // A link change sets the DL status event; unmasked it stays out of the IRQ field.
  ASSERT_TRUE(rig->segment.cut_link(4).ok());
  EXPECT_EQ(rig->read(Command::FPRD, 0x1000, reg::kType, 1).irq, 0);
  EXPECT_EQ(rig->write16(0x1003, reg::kEcatEventMask, 0x0004), 1);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1000, reg::kType, 1).irq & 0x0004, 0x0004);  // any datagram carries it
  EXPECT_NE(rig->read16(0x1003, reg::kEcatEventRequest) & 0x0004, 0);
  (void)rig->read16(0x1003, reg::kDlStatus);  // reading DL status acknowledges the event
  EXPECT_EQ(rig->read16(0x1003, reg::kEcatEventRequest) & 0x0004, 0);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1000, reg::kType, 1).irq, 0);
}

TEST_F(Registers, LostLinkCounterCountsAndClearsOnWrite) {
  ASSERT_TRUE(rig->segment.cut_link(4).ok());
  ASSERT_TRUE(rig->segment.restore_link(4).ok());
  ASSERT_TRUE(rig->segment.cut_link(4).ok());
  ASSERT_TRUE(rig->segment.restore_link(4).ok());
  // Slave 3 lost the link on port 1 twice.
  EXPECT_EQ(rig->read(Command::FPRD, 0x1003, static_cast<std::uint16_t>(reg::kLostLinkCounter + 1), 1).data[0], 2);
  EXPECT_EQ(rig->write(Command::FPWR, 0x1003, reg::kLostLinkCounter, {0, 0, 0, 0}).wkc, 1);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1003, static_cast<std::uint16_t>(reg::kLostLinkCounter + 1), 1).data[0], 0);
}

// ET1100/ET1200 datasheet, error counters: a write to any of 0x0300-0x030B clears all twelve RX and
// forwarded RX error counters (the value written is ignored), a write to 0x0310-0x0313 all four
// lost-link counters; each group only by a write inside it (ctl diag --reset writes them).
TEST_F(Registers, ErrorCountersAreClearedByGroupAsTheDatasheetSays) {
  const std::size_t elbow = 19;  // l_elbow; l_wrist_yaw (20) behind it sees forwarded errors
  ASSERT_TRUE(rig->segment.corrupt_port(elbow, 0, 3).ok());
  ASSERT_TRUE(rig->segment.cut_link(elbow + 1).ok());
  ASSERT_TRUE(rig->segment.restore_link(elbow + 1).ok());
  for (int i = 0; i < 4; ++i) (void)rig->read(Command::BRD, 0, reg::kType, 1);
  const auto counters = [&](std::uint16_t station) {
    return rig->read(Command::FPRD, station, reg::kRxErrorCounter, reg::kErrorCountersLength).data;
  };
  const std::uint16_t station = 0x1013;
  std::vector<std::uint8_t> before = counters(station);
  ASSERT_EQ(before[0], 3) << "invalid frames on port 0";
  ASSERT_EQ(before[0x09], 3) << "forwarded errors on port 1 (the damaged frames coming back)";
  ASSERT_NE(before[0x11], 0) << "lost link on port 1";
  // One byte written in the RX group (forwarded counter of port 3, value ignored): the whole group.
  EXPECT_EQ(rig->write(Command::FPWR, station, static_cast<std::uint16_t>(reg::kForwardedRxErrorCounter + 3), {0x55}).wkc, 1);
  std::vector<std::uint8_t> after = counters(station);
  for (std::size_t i = 0; i < 0x0C; ++i) EXPECT_EQ(after[i], 0) << "0x03" << std::hex << i;
  EXPECT_EQ(after[0x11], before[0x11]) << "the lost-link counters are another group";
  EXPECT_EQ(rig->write(Command::FPWR, station, static_cast<std::uint16_t>(reg::kLostLinkCounter + 2), {0}).wkc, 1);
  after = counters(station);
  for (std::size_t i = 0x10; i < 0x14; ++i) EXPECT_EQ(after[i], 0) << "0x03" << std::hex << i;
}

TEST_F(Registers, WatchdogRegistersHoldTheirResetValuesAndAreWritable) {
  EXPECT_EQ(rig->read16(0x1002, reg::kWatchdogDivider), 0x09C2);
  EXPECT_EQ(rig->read16(0x1002, reg::kWatchdogTimePdi), 1000);
  EXPECT_EQ(rig->read16(0x1002, reg::kWatchdogTimeProcessData), 1000);
  EXPECT_EQ(rig->write16(0x1002, reg::kWatchdogTimeProcessData, 250), 1);
  EXPECT_EQ(rig->read16(0x1002, reg::kWatchdogTimeProcessData), 250);
  EXPECT_EQ(rig->read16(0x1002, reg::kWatchdogStatusProcessData), 0x0001);
}

TEST_F(Registers, UserRamAndDcRegistersKeepWhatTheMasterWrites) {
  EXPECT_EQ(rig->write(Command::FPWR, 0x1002, 0x0F80, {1, 2, 3, 4}).wkc, 1);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1002, 0x0F80, 4).data, (std::vector<std::uint8_t>{1, 2, 3, 4}));
  EXPECT_EQ(rig->write(Command::FPWR, 0x1002, reg::kDcSystemTimeOffset, le64(0x1122334455667788ULL)).wkc, 1);
  EXPECT_EQ(from_le(rig->read(Command::FPRD, 0x1002, reg::kDcSystemTimeOffset, 8).data), 0x1122334455667788ULL);
  EXPECT_EQ(rig->write(Command::FPWR, 0x1002, reg::kDcSystemTimeDelay, le32(1234)).wkc, 1);
  EXPECT_EQ(from_le(rig->read(Command::FPRD, 0x1002, reg::kDcSystemTimeDelay, 4).data), 1234u);
  EXPECT_EQ(rig->read16(0x1002, reg::kDcSpeedCounterStart), 0x1000);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1002, reg::kDcTimeDiffFilterDepth, 2).data, (std::vector<std::uint8_t>{0x04, 0x0C}));
}

TEST_F(Registers, PdiWatchdogExpiresWhenTheApplicationHangs) {
  ASSERT_TRUE(rig->segment.freeze(5, true).ok());
  rig->wait(50 * hal::kNsPerMs);
  EXPECT_NE(rig->read16(0x1005, reg::kDlStatus) & reg::kDlStatusPdiWatchdog, 0);
  rig->wait(60 * hal::kNsPerMs);  // 100 ms PDI watchdog by default
  EXPECT_EQ(rig->read16(0x1005, reg::kDlStatus) & reg::kDlStatusPdiWatchdog, 0);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1005, 0x0443, 1).data[0], 1);
  ASSERT_TRUE(rig->segment.freeze(5, false).ok());
  EXPECT_NE(rig->read16(0x1005, reg::kDlStatus) & reg::kDlStatusPdiWatchdog, 0);
}

}  // namespace
}  // namespace rescue::drivers::testing
