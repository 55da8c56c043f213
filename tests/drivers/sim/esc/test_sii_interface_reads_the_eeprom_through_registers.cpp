// The SII EEPROM interface (0x0500-0x050F) as masters use it: command and address written in one
// datagram, busy for a while in virtual time, then 4 or 8 bytes of data; errors for addresses
// beyond the EEPROM, unknown commands and writes without write enable; writes and reload; the
// configuration area's CRC checked at power-up.
#include <vector>

#include "tests/support/segment_test_support.hpp"
#include "tests/support/sii_image_device.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr std::uint16_t kStation = 0x1000;

std::vector<std::uint8_t> command(std::uint16_t control, std::uint32_t word_address) {
  std::vector<std::uint8_t> c = le16(control);
  const std::vector<std::uint8_t> a = le32(word_address);
  c.insert(c.end(), a.begin(), a.end());
  return c;
}

std::uint16_t image_word(const TestDevice& device, std::size_t word) {
  const ConstByteSpan sii = device.sii_image();
  return static_cast<std::uint16_t>(sii[2 * word] | (sii[2 * word + 1] << 8));
}

class SiiInterface : public ::testing::Test {
 protected:
  void use(const EscConfig& config) {
    rig = Rig::single(config, 0x4321);
    rig->assign_station_addresses();
  }
  std::uint16_t control() { return rig->read16(kStation, reg::kSiiControl); }
  std::unique_ptr<Rig> rig;
};

TEST_F(SiiInterface, EightByteReadIsBusyThenDeliversFourWords) {
  use(junction_esc_config());  // ET1100 class: 8-byte reads
  EXPECT_EQ(control(), reg::kSiiRead8Bytes);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandRead, 0x0008)).wkc, 1);
  // Busy with the command bits showing, as on real ESCs (0x8140 for an 8-byte ESC).
  EXPECT_EQ(control(), reg::kSiiBusy | reg::kSiiCommandRead | reg::kSiiRead8Bytes);
  rig->wait(500 * hal::kNsPerUs);
  EXPECT_EQ(control(), reg::kSiiRead8Bytes);
  const auto data = rig->read(Command::FPRD, kStation, reg::kSiiData, 8).data;
  for (std::size_t w = 0; w < 4; ++w) {
    EXPECT_EQ(static_cast<std::uint16_t>(data[2 * w] | (data[2 * w + 1] << 8)), image_word(rig->device(), 8 + w)) << w;
  }
}

TEST_F(SiiInterface, FourByteReadFillsOnlyTwoWords) {
  use(joint_esc_config());  // 4-byte reads
  EXPECT_EQ(control() & reg::kSiiRead8Bytes, 0);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiData, std::vector<std::uint8_t>(8, 0xEE)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandRead, 0x0004)).wkc, 1);
  rig->wait(500 * hal::kNsPerUs);
  const auto data = rig->read(Command::FPRD, kStation, reg::kSiiData, 8).data;
  EXPECT_EQ(static_cast<std::uint16_t>(data[0] | (data[1] << 8)), 0x4321);  // word 4: the alias
  EXPECT_EQ(static_cast<std::uint16_t>(data[2] | (data[3] << 8)), image_word(rig->device(), 5));
  EXPECT_EQ(data[4], 0xEE);  // untouched
  EXPECT_EQ(data[7], 0xEE);
}

TEST_F(SiiInterface, WritesWhileBusyAreIgnored) {
  use(junction_esc_config());
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandRead, 0x0008)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandRead, 0x0010)).wkc, 1);
  EXPECT_EQ(rig->read(Command::FPRD, kStation, reg::kSiiAddress, 4).data, le32(0x0008));
  rig->wait(500 * hal::kNsPerUs);
  EXPECT_EQ(static_cast<std::uint16_t>(from_le(rig->read(Command::FPRD, kStation, reg::kSiiData, 2).data)), image_word(rig->device(), 8));
}

TEST_F(SiiInterface, AddressBeyondTheEepromIsACommandErrorUntilCleared) {
  use(junction_esc_config());
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandRead, 0x8000)).wkc, 1);
  EXPECT_EQ(control() & (reg::kSiiCommandError | reg::kSiiBusy), reg::kSiiCommandError);
  EXPECT_EQ(rig->write16(kStation, reg::kSiiControl, 0x0000), 1);  // NOP clears the error bits
  EXPECT_EQ(control() & reg::kSiiCommandError, 0);
  EXPECT_EQ(rig->write16(kStation, reg::kSiiControl, 0x0300), 1);  // command 3 does not exist
  EXPECT_EQ(control() & reg::kSiiCommandError, reg::kSiiCommandError);
}

TEST_F(SiiInterface, WriteNeedsWriteEnableAndReloadAppliesTheNewAlias) {
  use(junction_esc_config());
  EXPECT_EQ(rig->read16(kStation, reg::kStationAlias), 0x4321);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiData, le16(0x2468)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandWrite, 0x0004)).wkc, 1);
  EXPECT_EQ(control() & reg::kSiiWriteError, reg::kSiiWriteError);  // no write enable
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandWrite | reg::kSiiWriteEnable, 0x0004)).wkc, 1);
  EXPECT_EQ(control() & (reg::kSiiBusy | reg::kSiiWriteError), reg::kSiiBusy);
  rig->wait(6 * hal::kNsPerMs);  // EEPROM write time
  EXPECT_EQ(control() & (reg::kSiiBusy | reg::kSiiWriteEnable), 0);  // write enable clears itself
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandRead, 0x0004)).wkc, 1);
  rig->wait(500 * hal::kNsPerUs);
  EXPECT_EQ(rig->read16(kStation, reg::kSiiData), 0x2468);
  EXPECT_EQ(rig->read16(kStation, reg::kStationAlias), 0x4321);  // not before a reload
  // The configuration area's CRC must be right for a reload to take: fix word 7 first.
  std::array<std::uint8_t, 14> area{};
  const ConstByteSpan sii = rig->device().sii_image();
  for (std::size_t i = 0; i < 14; ++i) area[i] = sii[i];
  area[8] = 0x68;
  area[9] = 0x24;
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiData, le16(sii_config_crc(ConstByteSpan(area)))).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandWrite | reg::kSiiWriteEnable, 0x0007)).wkc, 1);
  rig->wait(6 * hal::kNsPerMs);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandReload, 0)).wkc, 1);
  rig->wait(hal::kNsPerMs);
  EXPECT_EQ(rig->read16(kStation, reg::kStationAlias), 0x2468);
}

TEST_F(SiiInterface, ReadsTheWholeImageWordByWord) {
  use(joint_esc_config());
  const std::size_t words = rig->device().sii_image().size() / 2;
  for (std::size_t w = 0; w < words; w += 2) {
    ASSERT_EQ(rig->write(Command::FPWR, kStation, reg::kSiiControl, command(reg::kSiiCommandRead, static_cast<std::uint32_t>(w))).wkc, 1);
    do {
      rig->wait(100 * hal::kNsPerUs);
    } while ((control() & reg::kSiiBusy) != 0);
    const auto data = rig->read(Command::FPRD, kStation, reg::kSiiData, 4).data;
    EXPECT_EQ(static_cast<std::uint16_t>(data[0] | (data[1] << 8)), image_word(rig->device(), w)) << w;
    if (w + 1 < words) {
      EXPECT_EQ(static_cast<std::uint16_t>(data[2] | (data[3] << 8)), image_word(rig->device(), w + 1)) << w;
    }
  }
}

// The EEPROM image of a device whose configuration-area CRC is broken.
std::vector<std::uint8_t> bad_crc_image() {
  SiiIdentity id{};
  id.station_alias = 0x0777;
  std::vector<std::uint8_t> image = rescue::testing::SiiImageDevice::minimal_image(id, "bad");
  image[14] = static_cast<std::uint8_t>(image[14] ^ 0xFF);
  return image;
}

TEST(SiiConfigurationArea, BadChecksumLeavesDeviceInformationUnloaded) {
  rescue::testing::SiiImageDevice device(bad_crc_image(), ProcessDataLayout{});
  SimulatedSegment segment;
  SegmentSlave s;
  s.esc = joint_esc_config();
  s.device = &device;
  ASSERT_TRUE(segment.build(Span<const SegmentSlave>(&s, 1), 0).ok());
  const Esc& esc = segment.esc(0);
  EXPECT_EQ(esc.register_u16(reg::kSiiControl) & (reg::kSiiChecksumError | reg::kSiiDeviceInfoError),
            reg::kSiiChecksumError | reg::kSiiDeviceInfoError);
  EXPECT_EQ(esc.register_u16(reg::kStationAlias), 0);               // not loaded
  EXPECT_EQ(esc.register_u16(reg::kDlStatus) & reg::kDlStatusPdiOperational, 0);
}

}  // namespace
}  // namespace rescue::drivers::testing
