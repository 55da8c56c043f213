// The SII reader reads what the master uses, not every byte (sii_reader.hpp; docs/master.md "SII
// reads at bring-up"). On the simulated robot (virtual time), with three real device images served
// behind it (../shared/vectors/sii):
//   - every image read parses to what the whole EEPROM parses to: identity, mailbox, sync managers,
//     FMMUs, PDOs and their sizes, DC modes, and the device name, order and group strings;
//   - every byte it holds is the EEPROM's, except the header's reserved words and the strings General
//     does not name, which are zero, and only those (strings_skipped counts the strings' bytes);
//   - with all_strings the image is the EEPROM byte for byte, reserved words aside;
//   - the default read takes at most two thirds of the EEPROM reads and of the frames of the
//     whole read, and a drive's image 84 reads instead of 141 (157 before the header's reserved words
//     were skipped);
//   - a General category naming a string past the last one ends the read at the category's end.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/link/datagram_link.hpp"
#include "ecat/sii/sii.hpp"
#include "ecat/sii/sii_reader.hpp"
#include "tests/support/shared_sii_images.hpp"
#include "tests/support/sii_image_device.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SiiImageDevice;
using testing::SimulatedRobotRig;

constexpr std::size_t kReservedFrom = 0x3A;  // header words 0x1D..0x3D
constexpr std::size_t kReservedTo = 0x7C;

// The simulated robot with `extra` (if any) cabled behind its last slave.
std::unique_ptr<SimulatedRobotRig> robot_with(drivers::SlaveDevice* extra) {
  auto rig = std::make_unique<SimulatedRobotRig>(false);
  drivers::SegmentSlave slave;
  slave.name = "extra";
  slave.upstream = 22;
  slave.upstream_port = 1;
  slave.esc = drivers::joint_esc_config();
  slave.link_delay_ns = drivers::kPhyPairDelayNs + 5;
  slave.device = extra;
  rig->build({}, extra != nullptr ? &slave : nullptr);
  EXPECT_TRUE(rig->built.ok()) << rig->built.error().what;
  return rig;
}

struct Read {
  std::vector<SiiImage> images;
  SiiReadStats stats{};
};

Read read_all(SimulatedRobotRig& rig, std::size_t count, bool all_strings) {
  DatagramLink link(rig.nic);
  Read r;
  r.images.resize(count);
  SiiReadOptions options;
  options.all_strings = all_strings;
  const Result<SiiReadStats> stats = read_sii_images(link, Span<SiiImage>(r.images.data(), count), options);
  EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().what);
  if (stats.ok()) r.stats = stats.value();
  return r;
}

// The Strings category's body in a whole image: [begin, end), or {0, 0}.
std::pair<std::size_t, std::size_t> strings_body(ConstByteSpan image) {
  std::size_t at = kSiiHeaderBytes;
  while (at + 4 <= image.size()) {
    const std::uint16_t type = load_le16(image.data() + at);
    const std::size_t end = at + 4 + std::size_t{2} * load_le16(image.data() + at + 2);
    if (type == sii::kCategoryEnd) break;
    if (type == sii::kCategoryStrings) return {at + 4, end};
    at = end;
  }
  return {0, 0};
}

// Checks one slave's image as read against its whole EEPROM.
void expect_read_as_used(const SiiImage& read, ConstByteSpan eeprom, const std::string& who) {
  SCOPED_TRACE(who);
  ASSERT_EQ(read.error.code, Errc::ok) << read.error.what;
  ASSERT_TRUE(read.complete);
  const Result<sii::Sii> whole_parse = sii::Sii::parse(eeprom);
  const Result<sii::Sii> read_parse = sii::Sii::parse(read.view());
  ASSERT_TRUE(whole_parse.ok()) << whole_parse.error().what;
  ASSERT_TRUE(read_parse.ok()) << read_parse.error().what;
  const sii::Sii& whole = whole_parse.value();
  const sii::Sii& got = read_parse.value();
  EXPECT_EQ(got.identity.vendor_id, whole.identity.vendor_id);
  EXPECT_EQ(got.identity.product_code, whole.identity.product_code);
  EXPECT_EQ(got.identity.revision, whole.identity.revision);
  EXPECT_EQ(got.identity.serial_number, whole.identity.serial_number);
  EXPECT_EQ(got.config.station_alias, whole.config.station_alias);
  EXPECT_EQ(got.standard_mailbox.receive_offset, whole.standard_mailbox.receive_offset);
  EXPECT_EQ(got.standard_mailbox.send_size, whole.standard_mailbox.send_size);
  EXPECT_EQ(got.mailbox_protocols, whole.mailbox_protocols);
  EXPECT_EQ(got.eeprom_size_bytes, whole.eeprom_size_bytes);
  EXPECT_EQ(got.version, whole.version);
  EXPECT_EQ(got.has_general, whole.has_general);
  EXPECT_EQ(got.general.coe_details, whole.general.coe_details);
  EXPECT_EQ(got.name(), whole.name());
  EXPECT_EQ(got.order(), whole.order());
  EXPECT_EQ(got.group(), whole.group());
  EXPECT_EQ(got.string_count(), whole.string_count());
  EXPECT_EQ(got.category_count, whole.category_count);
  EXPECT_EQ(got.sync_managers.size(), whole.sync_managers.size());
  EXPECT_EQ(got.fmmus.size(), whole.fmmus.size());
  EXPECT_EQ(got.tx_pdos.size(), whole.tx_pdos.size());
  EXPECT_EQ(got.rx_pdos.size(), whole.rx_pdos.size());
  EXPECT_EQ(got.tx_entries.size(), whole.tx_entries.size());
  EXPECT_EQ(got.rx_entries.size(), whole.rx_entries.size());
  EXPECT_EQ(got.dc_modes.size(), whole.dc_modes.size());
  for (std::uint8_t sm = 0; sm < 4; ++sm) {
    EXPECT_EQ(got.default_bits_of_sync_manager(sm), whole.default_bits_of_sync_manager(sm)) << "SM" << int{sm};
  }

  // Byte for byte: the EEPROM's, or zero where reading was left out.
  ASSERT_LE(read.size, eeprom.size());
  const auto [strings_begin, strings_end] = strings_body(eeprom);
  std::size_t strings_zeroed = 0;
  for (std::size_t i = 0; i < read.size; ++i) {
    if (read.bytes[i] == eeprom[i]) continue;
    const bool reserved = i >= kReservedFrom && i < kReservedTo;
    const bool in_strings = i >= strings_begin && i < strings_end;
    EXPECT_TRUE(read.bytes[i] == 0 && (reserved || in_strings)) << "byte 0x" << std::hex << i;
    if (in_strings) ++strings_zeroed;
  }
  EXPECT_LE(strings_zeroed, read.strings_skipped);
  EXPECT_LE(read.strings_skipped, strings_end - strings_begin);
}

// The image read with all_strings: the EEPROM byte for byte, reserved words aside (and the end
// marker the reader puts in where a category would not fit its buffer).
void expect_read_whole(const SiiImage& whole, ConstByteSpan eeprom, const std::string& who) {
  SCOPED_TRACE(who);
  ASSERT_EQ(whole.error.code, Errc::ok) << whole.error.what;
  ASSERT_TRUE(whole.complete);
  EXPECT_EQ(whole.strings_skipped, 0u);
  ASSERT_LE(whole.size, eeprom.size());
  const std::size_t compared = whole.truncated ? whole.size - 2U : whole.size;
  for (std::size_t i = 0; i < compared; ++i) {
    if (i >= kReservedFrom && i < kReservedTo) continue;
    ASSERT_EQ(whole.bytes[i], eeprom[i]) << "byte 0x" << std::hex << i;
  }
}

TEST(SiiReader, ReadsWhatTheMasterUsesFromEverySlaveOfTheRobot) {
  auto rig = robot_with(nullptr);
  const Read used = read_all(*rig, kSlaveCount, false);
  const Read whole = read_all(*rig, kSlaveCount, true);
  ASSERT_EQ(used.images.size(), kSlaveCount);
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    const ConstByteSpan eeprom = rig->devices[p]->sii_image();
    expect_read_whole(whole.images[p], eeprom, "slave " + std::to_string(p));
    EXPECT_FALSE(whole.images[p].truncated);
    expect_read_as_used(used.images[p], eeprom, "slave " + std::to_string(p));
  }
  // A drive's PDO and sync names fill most of its strings: they are not read.
  const std::size_t drive = slave_position_of_joint(0);
  EXPECT_GT(used.images[drive].strings_skipped, 100u);
  EXPECT_LE(used.stats.frames * 3, whole.stats.frames * 2) << used.stats.frames << " against " << whole.stats.frames;
  EXPECT_LE(used.stats.reads * 3, whole.stats.reads * 2) << used.stats.reads << " against " << whole.stats.reads;
}

// One drive's reads: the robot's first two slaves are junctions, the third a drive (624 bytes, 4 bytes
// per read); reading three slaves costs the junctions' reads plus the drive's.
TEST(SiiReader, ADrivesImageTakes84ReadsInsteadOf141) {
  auto rig = robot_with(nullptr);
  ASSERT_EQ(read_all(*rig, 3, true).images[2].size, 624u);  // to its end marker
  const auto drive_reads = [&](bool all_strings) {
    return read_all(*rig, 3, all_strings).stats.reads - read_all(*rig, 2, all_strings).stats.reads;
  };
  EXPECT_EQ(drive_reads(false), 84u);
  EXPECT_EQ(drive_reads(true), 141u);  // every string; 157 before the header's reserved words were skipped
}

class RealDeviceImage : public ::testing::TestWithParam<const char*> {};

TEST_P(RealDeviceImage, IsReadAsTheMasterUsesIt) {
  std::vector<std::uint8_t> image = test::read_shared_sii(GetParam());
  if (image.empty()) GTEST_SKIP() << "needs " RESCUE_SHARED_DIR "/vectors/sii/" << GetParam() << " (shared vectors absent)";
  SiiImageDevice device(image);
  auto rig = robot_with(&device);
  const Read used = read_all(*rig, kSlaveCount + 1, false);
  const Read whole = read_all(*rig, kSlaveCount + 1, true);
  ASSERT_EQ(used.images.size(), kSlaveCount + 1);
  const SiiImage& read = used.images[kSlaveCount];
  // The AKD's image is longer than the reader's buffer: both reads end it at the same category.
  expect_read_whole(whole.images[kSlaveCount], ConstByteSpan(image.data(), image.size()), GetParam());
  EXPECT_EQ(read.truncated, whole.images[kSlaveCount].truncated);
  expect_read_as_used(read, whole.images[kSlaveCount].view(), GetParam());
  const Result<sii::Sii> parsed = sii::Sii::parse(read.view());
  ASSERT_TRUE(parsed.ok());
  EXPECT_FALSE(parsed.value().name().empty());
}

INSTANTIATE_TEST_SUITE_P(Vectors, RealDeviceImage, ::testing::Values("ek1100.bin", "el2828.bin", "akd.bin"));

TEST(SiiReader, AGeneralCategoryNamingAStringPastTheLastEndsAtTheCategorysEnd) {
  auto source = robot_with(nullptr);
  const ConstByteSpan drive_image = source->devices[slave_position_of_joint(0)]->sii_image();
  std::vector<std::uint8_t> image(drive_image.begin(), drive_image.end());
  // Find General and make its name index 200 (the drive has far fewer strings).
  std::size_t at = kSiiHeaderBytes;
  std::size_t general = 0;
  while (at + 4 <= image.size() && load_le16(&image[at]) != sii::kCategoryEnd) {
    if (load_le16(&image[at]) == sii::kCategoryGeneral) general = at + 4;
    at += 4 + std::size_t{2} * load_le16(&image[at + 2]);
  }
  ASSERT_NE(general, 0u);
  image[general + 3] = 200;
  SiiImageDevice device(image);
  auto rig = robot_with(&device);
  const Read used = read_all(*rig, kSlaveCount + 1, false);
  const SiiImage& read = used.images[kSlaveCount];
  ASSERT_EQ(read.error.code, Errc::ok) << read.error.what;
  EXPECT_TRUE(read.complete);
  EXPECT_EQ(read.strings_skipped, 0u);  // read to the category's end, looking for string 200
  const auto [begin, end] = strings_body(ConstByteSpan(image.data(), image.size()));
  EXPECT_TRUE(std::equal(image.begin() + static_cast<std::ptrdiff_t>(begin), image.begin() + static_cast<std::ptrdiff_t>(end),
                         read.bytes.begin() + static_cast<std::ptrdiff_t>(begin)));
  const Result<sii::Sii> parsed = sii::Sii::parse(read.view());
  ASSERT_TRUE(parsed.ok()) << parsed.error().what;
  EXPECT_TRUE(parsed.value().name().empty());
}

}  // namespace
}  // namespace rescue::ecat
