// The reader understands the capture files other tools write: classic pcap in both byte orders
// with micro- and nanosecond timestamps, pcapng in both byte orders, several sections, several
// interfaces, every timestamp resolution form, simple and obsolete packet blocks, blocks it has no
// use for, and the FCS and direction information.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "ecat/capture/capture_reader.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/capture_bytes.hpp"
#include "tests/support/read_frames.hpp"

namespace rescue::ecat {
namespace {

std::vector<std::uint8_t> frame_bytes(std::uint8_t index) {
  FrameBuilder b;
  b.reset(MacAddress{0x02, 0, 0, 0, 0, index});
  EXPECT_TRUE(b.add(Command::FPRD, index, make_address(0x1000, 0x0130), 2).ok());
  const ConstByteSpan f = b.finish();
  return std::vector<std::uint8_t>(f.begin(), f.end());
}

std::vector<CapturedFrame> read_all(const std::vector<std::uint8_t>& file, CaptureFormat expected_format) {
  const auto reader = CaptureReader::open(ConstByteSpan(file.data(), file.size()));
  EXPECT_TRUE(reader.ok() && reader.value().format() == expected_format);
  return test::read_all_frames(file);
}

bool same_bytes(ConstByteSpan a, const std::vector<std::uint8_t>& b) {
  return a.size() == b.size() && std::equal(b.begin(), b.end(), a.begin());
}

class ClassicPcap : public testing::TestWithParam<std::tuple<bool, bool>> {};

TEST_P(ClassicPcap, ReadsRecordsWithTimestampsInNanoseconds) {
  const bool big = std::get<0>(GetParam());
  const bool nanos = std::get<1>(GetParam());
  const auto f1 = frame_bytes(1);
  const auto f2 = frame_bytes(2);
  test::PcapBuilder pcap(big, nanos);
  pcap.record(1654432544, nanos ? 901825123 : 901825, f1).record(1654432545, 7, f2, 1514);
  const auto frames = read_all(pcap.bytes(), CaptureFormat::pcap);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_EQ(frames[0].number, 1U);
  EXPECT_EQ(frames[1].number, 2U);
  EXPECT_TRUE(same_bytes(frames[0].bytes, f1));
  EXPECT_TRUE(same_bytes(frames[1].bytes, f2));
  EXPECT_EQ(frames[0].timestamp_ns, nanos ? 1654432544901825123ULL : 1654432544901825000ULL);
  EXPECT_EQ(frames[1].timestamp_ns, 1654432545000000000ULL + (nanos ? 7U : 7000U));
  EXPECT_EQ(frames[1].original_length, 1514U);
  EXPECT_EQ(frames[0].link_type, capture::kLinkTypeEthernet);
  EXPECT_EQ(frames[0].fcs_length, 0);
  EXPECT_EQ(frames[0].direction, FrameDirection::unknown);
}

INSTANTIATE_TEST_SUITE_P(ByteOrderAndResolution, ClassicPcap,
                         testing::Combine(testing::Bool(), testing::Bool()),
                         [](const testing::TestParamInfo<std::tuple<bool, bool>>& p) {
                           return std::string(std::get<0>(p.param) ? "big_endian" : "little_endian") +
                                  (std::get<1>(p.param) ? "_ns" : "_us");
                         });

TEST(ClassicPcapFile, EmptyFileHasNoFrames) {
  test::PcapBuilder pcap(false, false);
  EXPECT_TRUE(read_all(pcap.bytes(), CaptureFormat::pcap).empty());
}

TEST(ClassicPcapFile, FcsLengthBitsOfTheLinkTypeField) {
  // Link type 1 with "FCS length known: 2 x 16 bits".
  test::PcapBuilder pcap(false, false, capture::kLinkTypeEthernet | capture::kPcapFcsPresentFlag | (2U << 28));
  pcap.record(1, 0, frame_bytes(1));
  const auto frames = read_all(pcap.bytes(), CaptureFormat::pcap);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(frames[0].link_type, capture::kLinkTypeEthernet);
  EXPECT_EQ(frames[0].fcs_length, 4);
}

class Pcapng : public testing::TestWithParam<bool> {};

TEST_P(Pcapng, EnhancedPacketsWithDirectionAndDefaultMicroseconds) {
  const auto f1 = frame_bytes(1);
  const auto f2 = frame_bytes(2);
  test::PcapngBuilder ng(GetParam());
  ng.interface().packet(0, 1654432544901825ULL, f1, 2U).packet(0, 1654432544901826ULL, f2, 1U, 1000U);
  const auto frames = read_all(ng.bytes(), CaptureFormat::pcapng);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_TRUE(same_bytes(frames[0].bytes, f1));
  EXPECT_EQ(frames[0].timestamp_ns, 1654432544901825000ULL);
  EXPECT_EQ(frames[0].direction, FrameDirection::outbound);
  EXPECT_EQ(frames[1].direction, FrameDirection::inbound);
  EXPECT_EQ(frames[1].original_length, 1000U);
  EXPECT_EQ(frames[1].number, 2U);
}

TEST_P(Pcapng, TimestampResolutionsAndOffset) {
  const auto f = frame_bytes(3);
  test::PcapngBuilder ng(GetParam());
  ng.interface(capture::kLinkTypeEthernet, 0, std::uint8_t{9})                       // ns
      .interface(capture::kLinkTypeEthernet, 0, std::uint8_t{3})                     // ms
      .interface(capture::kLinkTypeEthernet, 0, std::uint8_t{0x80 | 20})             // 2^-20 s
      .interface(capture::kLinkTypeEthernet, 0, std::uint8_t{12}, std::int64_t{-10})  // ps, 10 s earlier
      .packet(0, 1234567890123456789ULL, f)
      .packet(1, 1234567ULL, f)
      .packet(2, (5ULL << 20) | (1ULL << 19), f)  // 5.5 s
      .packet(3, 20'000'000'000'123ULL, f);       // 20.000000000123 s - 10 s
  const auto frames = read_all(ng.bytes(), CaptureFormat::pcapng);
  ASSERT_EQ(frames.size(), 4U);
  EXPECT_EQ(frames[0].timestamp_ns, 1234567890123456789ULL);
  EXPECT_EQ(frames[1].timestamp_ns, 1234567000000ULL);
  EXPECT_EQ(frames[2].timestamp_ns, 5'500'000'000ULL);
  EXPECT_EQ(frames[3].timestamp_ns, 10'000'000'000ULL);
  EXPECT_EQ(frames[3].interface_id, 3U);
}

TEST_P(Pcapng, SimpleAndObsoletePacketBlocks) {
  const auto f1 = frame_bytes(1);
  const auto f2 = frame_bytes(2);
  test::PcapngBuilder ng(GetParam());
  ng.interface(capture::kLinkTypeEthernet, 40).simple_packet(f1).obsolete_packet(0, 77, f2);
  const auto frames = read_all(ng.bytes(), CaptureFormat::pcapng);
  ASSERT_EQ(frames.size(), 2U);
  // The simple packet is cut to the interface's snap length of 40 bytes.
  ASSERT_EQ(frames[0].bytes.size(), 40U);
  EXPECT_TRUE(std::equal(f1.begin(), f1.begin() + 40, frames[0].bytes.begin()));
  EXPECT_EQ(frames[0].original_length, f1.size());
  EXPECT_EQ(frames[0].timestamp_ns, 0U);
  EXPECT_TRUE(same_bytes(frames[1].bytes, f2));
  EXPECT_EQ(frames[1].timestamp_ns, 77000U);
}

TEST_P(Pcapng, OtherBlocksAreSkippedAndFramesCountedAcrossThem) {
  const auto f = frame_bytes(4);
  test::PcapngBuilder ng(GetParam());
  ng.interface()
      .block(4, {0, 0, 0, 0})                      // name resolution (end of records)
      .packet(0, 1, f)
      .block(5, std::vector<std::uint8_t>(16, 0))  // interface statistics
      .block(0x00000BAD, {1, 2, 3})                // custom block
      .packet(0, 2, f);
  const auto frames = read_all(ng.bytes(), CaptureFormat::pcapng);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_EQ(frames[1].number, 2U);
}

TEST_P(Pcapng, InterfacesCarryTheirLinkTypeAndFcsLength) {
  const auto f = frame_bytes(5);
  test::PcapngBuilder ng(GetParam());
  ng.interface(101)  // raw IP
      .interface(capture::kLinkTypeEthernet, 0, std::nullopt, std::nullopt, std::uint8_t{4})
      .packet(0, 1, f)
      .packet(1, 2, f);
  const auto frames = read_all(ng.bytes(), CaptureFormat::pcapng);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_EQ(frames[0].link_type, 101);
  EXPECT_EQ(frames[1].link_type, capture::kLinkTypeEthernet);
  EXPECT_EQ(frames[1].fcs_length, 4);
}

INSTANTIATE_TEST_SUITE_P(ByteOrder, Pcapng, testing::Bool(), [](const testing::TestParamInfo<bool>& p) {
  return std::string(p.param ? "big_endian" : "little_endian");
});

TEST(PcapngFile, SectionsMayChangeByteOrderAndRestartInterfaceIds) {
  const auto f1 = frame_bytes(1);
  const auto f2 = frame_bytes(2);
  test::PcapngBuilder ng(false);
  ng.interface(capture::kLinkTypeEthernet, 0, std::uint8_t{9}).packet(0, 5, f1);
  ng.section(true).interface(capture::kLinkTypeEthernet).packet(0, 6, f2);
  const auto frames = read_all(ng.bytes(), CaptureFormat::pcapng);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_EQ(frames[0].timestamp_ns, 5U);
  EXPECT_EQ(frames[1].timestamp_ns, 6000U);  // second section's interface: microseconds
  EXPECT_TRUE(same_bytes(frames[1].bytes, f2));
}

// The section length is advisory (-1 = unknown in the spec); the reader walks blocks by their own
// lengths, so a bogus one (the fuzzer's 0xffffffffffffffc9) or one that disagrees with the blocks that
// follow reads the same frames.
TEST(PcapngFile, SectionLengthIsAdvisoryAndNotRead) {
  const auto f1 = frame_bytes(1);
  test::PcapngBuilder ng(false);
  ng.interface().packet(0, 5, f1);
  const std::vector<std::uint8_t> original = ng.bytes();
  for (const std::uint64_t section_length : std::vector<std::uint64_t>{0xFFFFFFFFFFFFFFC9ULL, 0, 16}) {
    std::vector<std::uint8_t> file = original;
    for (std::size_t i = 0; i < 8; ++i) file[16 + i] = static_cast<std::uint8_t>(section_length >> (8 * i));
    const auto frames = read_all(file, CaptureFormat::pcapng);
    ASSERT_EQ(frames.size(), 1U) << section_length;
    EXPECT_TRUE(same_bytes(frames[0].bytes, f1));
  }
}

TEST(PcapngFile, SectionWithoutPacketsIsEmpty) {
  test::PcapngBuilder ng(false);
  EXPECT_TRUE(read_all(ng.bytes(), CaptureFormat::pcapng).empty());
}

TEST(PcapngTimestamp, ConversionEdges) {
  EXPECT_EQ(pcapng_timestamp_ns(0xFFFFFFFFFFFFFFFFULL, 9, 0).value(), 0xFFFFFFFFFFFFFFFFULL);
  EXPECT_FALSE(pcapng_timestamp_ns(0xFFFFFFFFFFFFFFFFULL, 6, 0).ok());  // us -> ns overflows
  EXPECT_EQ(pcapng_timestamp_ns(123456789, 18, 0).value(), 0U);        // attoseconds
  EXPECT_EQ(pcapng_timestamp_ns(0xFFFFFFFFFFFFFFFFULL, 28, 0).value(), 1U);  // 1.8e19 / 1e19
  EXPECT_EQ(pcapng_timestamp_ns(0, 29, 0).error().code, Errc::unsupported);
  EXPECT_EQ(pcapng_timestamp_ns(1ULL << 63, 0x80 | 63, 0).value(), 1'000'000'000ULL);
  EXPECT_EQ(pcapng_timestamp_ns(3ULL << 62, 0x80 | 63, 0).value(), 1'500'000'000ULL);
  EXPECT_EQ(pcapng_timestamp_ns(0, 0x80 | 64, 0).error().code, Errc::unsupported);
  EXPECT_EQ(pcapng_timestamp_ns(5, 0, -5).value(), 0U);
  EXPECT_EQ(pcapng_timestamp_ns(5, 0, -6).error().code, Errc::out_of_range);
  EXPECT_EQ(pcapng_timestamp_ns(0, 9, 9'300'000'000LL).error().code, Errc::out_of_range);
}

}  // namespace
}  // namespace rescue::ecat
