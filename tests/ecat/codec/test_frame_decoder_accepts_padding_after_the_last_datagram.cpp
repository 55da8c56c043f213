// Real masters pad an odd-length datagram to an even length: the EtherCAT header's length then
// covers a byte no datagram uses (a 1-byte BWR in a frame whose header says 14). Wireshark shows it
// as padding; so does the decoder (FrameHeader::padding), while real garbage after the last
// datagram (a non-zero byte, or room for a whole datagram whose more-follows bit is missing) stays
// an error. parse_ecat applies the same rules to an EtherCAT header at any offset (cooked captures).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "ecat/codec/frame.hpp"

namespace rescue::ecat {
namespace {

// Ethernet header, EtherCAT header saying `ecat_length`, one 1-byte BWR (13 bytes), then `tail`.
std::vector<std::uint8_t> one_byte_bwr(std::uint16_t ecat_length, const std::vector<std::uint8_t>& tail) {
  std::vector<std::uint8_t> f(14, 0xFF);
  store_be16(f.data() + 12, kEtherTypeEtherCAT);
  f.push_back(0);
  f.push_back(0);
  store_le16(f.data() + 14, static_cast<std::uint16_t>(ecat_length | 0x1000));
  const std::vector<std::uint8_t> bwr{0x08, 0x05, 0x00, 0x00, 0x20, 0x01, 0x01, 0x00, 0x00, 0x00, 0x02, 0x03, 0x00};
  f.insert(f.end(), bwr.begin(), bwr.end());
  f.insert(f.end(), tail.begin(), tail.end());
  f.resize(60, 0);  // Ethernet minimum: zero padding outside the EtherCAT length
  return f;
}

TEST(FramePadding, OneByteBwrInAFrameWhoseHeaderSays14) {
  const auto f = one_byte_bwr(14, {0x00});
  const auto r = FrameView::parse(ConstByteSpan(f.data(), f.size()));
  ASSERT_TRUE(r.ok()) << r.error().what;
  EXPECT_EQ(r.value().datagram_count(), 1U);
  EXPECT_EQ(r.value().header().ecat_length, 14U);
  EXPECT_EQ(r.value().header().padding, 1U);
  EXPECT_EQ(r.value().header().ecat_end(), 16U + 14U);
  const DatagramView d = *r.value().begin();
  EXPECT_EQ(d.command(), Command::BWR);
  EXPECT_EQ(d.length(), 1U);
  EXPECT_EQ(d.wkc(), 3U);
}

TEST(FramePadding, NoPaddingWhenTheLengthIsExact) {
  const auto f = one_byte_bwr(13, {});
  const auto r = FrameView::parse(ConstByteSpan(f.data(), f.size()));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().header().padding, 0U);
}

TEST(FramePadding, UpToElevenZeroBytesArePadding) {
  const auto f = one_byte_bwr(13 + 11, std::vector<std::uint8_t>(11, 0));
  const auto r = FrameView::parse(ConstByteSpan(f.data(), f.size()));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().header().padding, 11U);
}

TEST(FramePadding, ANonZeroByteIsGarbage) {
  const auto f = one_byte_bwr(14, {0xA5});
  const auto r = FrameView::parse(ConstByteSpan(f.data(), f.size()));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::malformed);
  EXPECT_STREQ(r.error().what, "bytes after last datagram");
  EXPECT_EQ(r.error().detail0, 1U);
  EXPECT_EQ(r.error().detail1, 16U + 13U);
}

TEST(FramePadding, RoomForAWholeDatagramIsGarbage) {
  // 12 zero bytes are an empty NOP whose more-follows bit the master forgot: not padding.
  const auto f = one_byte_bwr(13 + 12, std::vector<std::uint8_t>(12, 0));
  const auto r = FrameView::parse(ConstByteSpan(f.data(), f.size()));
  ASSERT_FALSE(r.ok());
  EXPECT_STREQ(r.error().what, "bytes after last datagram");
}

TEST(FramePadding, ParseEcatReadsTheSameFrameAtAnyOffset) {
  const auto f = one_byte_bwr(14, {0x00});
  for (const std::size_t prefix : {std::size_t{0}, std::size_t{16}, std::size_t{20}}) {
    std::vector<std::uint8_t> cooked(prefix, 0x77);
    cooked.insert(cooked.end(), f.begin() + 14, f.begin() + 30);
    const auto r = FrameView::parse_ecat(ConstByteSpan(cooked.data(), cooked.size()), prefix);
    ASSERT_TRUE(r.ok()) << r.error().what;
    EXPECT_EQ(r.value().header().ecat_offset, prefix);
    EXPECT_EQ(r.value().header().padding, 1U);
    EXPECT_EQ(r.value().datagram_count(), 1U);
    EXPECT_EQ((*r.value().begin()).wkc(), 3U);
  }
}

TEST(FramePadding, ParseEcatRefusesAnOffsetPastTheEnd) {
  const std::vector<std::uint8_t> bytes(5, 0);
  for (std::size_t at = 4; at <= 8; ++at) {
    const auto r = FrameView::parse_ecat(ConstByteSpan(bytes.data(), bytes.size()), at);
    ASSERT_FALSE(r.ok());
    EXPECT_STREQ(r.error().what, "ecat header");
    EXPECT_EQ(r.error().detail1, at);
  }
}

}  // namespace
}  // namespace rescue::ecat
