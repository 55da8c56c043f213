// Size edges of the codec: empty datagrams, the largest datagram, the largest number of datagrams,
// Ethernet padding, a captured FCS, an 802.1Q tag, and the builder refusing what does not fit.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "ecat/codec/frame.hpp"

namespace rescue::ecat {
namespace {

std::vector<std::uint8_t> copy_of(ConstByteSpan s) { return std::vector<std::uint8_t>(s.begin(), s.end()); }

TEST(FrameBoundaries, EmptyDatagramIsTwelveBytesAndPaddedTo60) {
  FrameBuilder b;
  ASSERT_TRUE(b.add(Command::BRD, 0, 0, 0).ok());
  const ConstByteSpan frame = b.finish();
  EXPECT_EQ(frame.size(), kMinFrameSize);
  const auto parsed = FrameView::parse(frame);
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(parsed.value().header().ecat_length, kDatagramOverhead);
  EXPECT_EQ(parsed.value().header().ecat_end(), 28U);
  const DatagramView d = *parsed.value().begin();
  EXPECT_EQ(d.length(), 0);
  EXPECT_TRUE(d.data().empty());
  for (std::size_t i = 28; i < frame.size(); ++i) EXPECT_EQ(frame[i], 0) << "padding byte " << i;
}

TEST(FrameBoundaries, UnpaddedFrameAsCapturedOnTheSenderStillParses) {
  // Masters' own frames appear unpadded (29 bytes) in captures taken on the sending host.
  FrameBuilder b;
  ASSERT_TRUE(b.add(Command::BRD, 0, 0, 1).ok());
  const std::vector<std::uint8_t> frame = copy_of(b.finish());
  const auto parsed = FrameView::parse(ConstByteSpan(frame.data(), 29));
  ASSERT_TRUE(parsed.ok()) << parsed.error().what;
  EXPECT_EQ(parsed.value().header().ecat_end(), 29U);
}

TEST(FrameBoundaries, LargestDatagramFillsTheFrameExactly) {
  FrameBuilder b;
  EXPECT_EQ(b.remaining_data_capacity(), kMaxDatagramDataLength);
  const std::vector<std::uint8_t> data(kMaxDatagramDataLength, 0x5A);
  ASSERT_TRUE(b.add(Command::LRW, 9, 0x10000, static_cast<std::uint16_t>(data.size()), ConstByteSpan(data.data(), data.size()))
                  .ok());
  EXPECT_EQ(b.remaining_data_capacity(), 0U);
  const ConstByteSpan frame = b.finish();
  EXPECT_EQ(frame.size(), kMaxFrameSize);
  const auto parsed = FrameView::parse(frame);
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ((*parsed.value().begin()).length(), kMaxDatagramDataLength);
  EXPECT_EQ(parsed.value().header().ecat_end(), kMaxFrameSize);
}

TEST(FrameBoundaries, OneByteMoreThanTheLargestDatagramIsRefused) {
  FrameBuilder b;
  const auto r = b.add(Command::LRW, 0, 0, static_cast<std::uint16_t>(kMaxDatagramDataLength + 1));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::invalid_argument);
  EXPECT_EQ(b.datagram_count(), 0U);
}

TEST(FrameBoundaries, HundredTwentyFourEmptyDatagramsFitAndTheNextIsRefused) {
  ASSERT_EQ(kMaxDatagramsPerFrame, 124U);
  FrameBuilder b;
  for (std::size_t i = 0; i < kMaxDatagramsPerFrame; ++i) {
    ASSERT_TRUE(b.add(Command::NOP, static_cast<std::uint8_t>(i), 0, 0).ok()) << i;
  }
  const auto refused = b.add(Command::NOP, 0, 0, 0);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, Errc::capacity_exceeded);
  EXPECT_EQ(refused.error().detail0, 124U);
  EXPECT_EQ(b.datagram_count(), 124U);

  const ConstByteSpan frame = b.finish();
  EXPECT_EQ(frame.size(), kEthernetHeaderSize + kEcatHeaderSize + 124 * kDatagramOverhead);
  const auto parsed = FrameView::parse(frame);
  ASSERT_TRUE(parsed.ok()) << parsed.error().what;
  EXPECT_EQ(parsed.value().datagram_count(), 124U);
  std::size_t n = 0;
  for (const DatagramView d : parsed.value()) {
    EXPECT_EQ(d.index(), static_cast<std::uint8_t>(n));
    EXPECT_EQ(d.more_follows(), n + 1 < 124);
    ++n;
  }
  EXPECT_EQ(n, 124U);
}

TEST(FrameBoundaries, RefusalLeavesTheFrameUnchanged) {
  FrameBuilder b;
  ASSERT_TRUE(b.add(Command::LRD, 0, 0, static_cast<std::uint16_t>(kMaxDatagramDataLength - 20)).ok());
  const std::vector<std::uint8_t> before = copy_of(b.finish());
  ASSERT_FALSE(b.add(Command::FPRD, 1, 0, 9).ok());  // 12 + 9 > 20 bytes left
  EXPECT_EQ(copy_of(b.finish()), before);
  ASSERT_TRUE(b.add(Command::FPRD, 1, 0, 8).ok());  // exactly fills the frame
  EXPECT_EQ(b.finish().size(), kMaxFrameSize);
}

TEST(FrameBoundaries, DataSizeMustMatchLength) {
  FrameBuilder b;
  const std::uint8_t two[2] = {1, 2};
  const auto r = b.add(Command::FPWR, 0, 0, 3, ConstByteSpan(two));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::invalid_argument);
  const auto bad_command = b.add(static_cast<Command>(15), 0, 0, 0);
  ASSERT_FALSE(bad_command.ok());
  EXPECT_EQ(bad_command.error().code, Errc::invalid_argument);
}

TEST(FrameBoundaries, CapturedFcsAfterThePayloadIsIgnored) {
  FrameBuilder b;
  ASSERT_TRUE(b.add(Command::LRD, 0, 0, static_cast<std::uint16_t>(kMaxDatagramDataLength)).ok());
  std::vector<std::uint8_t> frame = copy_of(b.finish());
  frame.insert(frame.end(), {0xDE, 0xAD, 0xBE, 0xEF});  // 1518 bytes: maximal frame plus FCS
  const auto parsed = FrameView::parse(ConstByteSpan(frame.data(), frame.size()));
  ASSERT_TRUE(parsed.ok()) << parsed.error().what;
  EXPECT_EQ(parsed.value().header().ecat_end(), kMaxFrameSize);
}

TEST(FrameBoundaries, VlanTaggedFrameParsesWithItsTag) {
  FrameBuilder b;
  b.reset(MacAddress{0x02, 0, 0, 0, 0, 0x01});
  ASSERT_TRUE(b.add(Command::FPRD, 5, make_address(0x1001, 0x0130), 2).ok());
  std::vector<std::uint8_t> frame = copy_of(b.finish());
  // Insert 0x8100, TCI (priority 7, VLAN 0x123) after the MAC addresses.
  frame.insert(frame.begin() + 12, {0x81, 0x00, 0xE1, 0x23});
  const auto parsed = FrameView::parse(ConstByteSpan(frame.data(), frame.size()));
  ASSERT_TRUE(parsed.ok()) << parsed.error().what;
  const FrameHeader& h = parsed.value().header();
  EXPECT_TRUE(h.vlan_tagged);
  EXPECT_EQ(h.vlan_tci, 0xE123);
  EXPECT_EQ(h.ecat_offset, 18U);
  const DatagramView d = *parsed.value().begin();
  EXPECT_EQ(d.command(), Command::FPRD);
  EXPECT_EQ(d.adp(), 0x1001);
  EXPECT_EQ(d.ado(), 0x0130);
}

TEST(FrameBoundaries, FrameLongerThanTaggedFramePlusFcsIsRejected) {
  std::vector<std::uint8_t> frame(kMaxFrameSize + kVlanTagSize + 4 + 1, 0);
  const auto r = FrameView::parse(ConstByteSpan(frame.data(), frame.size()));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::malformed);
  EXPECT_STREQ(r.error().what, "frame too long");
  EXPECT_EQ(r.error().detail1, frame.size());
}

TEST(FrameBoundaries, BuilderResetStartsAFreshFrame) {
  FrameBuilder b;
  ASSERT_TRUE(b.add(Command::LRW, 0, 0, 100).ok());
  b.reset(MacAddress{0x02, 0, 0, 0, 0, 0x02});
  EXPECT_EQ(b.datagram_count(), 0U);
  ASSERT_TRUE(b.add(Command::BRD, 1, 0, 2).ok());
  const auto parsed = FrameView::parse(b.finish());
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(parsed.value().datagram_count(), 1U);
  EXPECT_EQ((*parsed.value().begin()).command(), Command::BRD);
  EXPECT_FALSE((*parsed.value().begin()).more_follows());
}

}  // namespace
}  // namespace rescue::ecat
