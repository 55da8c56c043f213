// Each way a frame can be inconsistent gives its own error value: the field (Error::what), the
// datagram (detail0, kFrameLevel for frame-level fields) and the byte offset of that field (detail1),
// as the table in ecat/codec/frame.hpp documents.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "ecat/codec/frame.hpp"

namespace rescue::ecat {
namespace {

// Three datagrams: FPRD len 2 at 16, LRW len 6 at 30, BRD len 1 at 48; ecat_end = 61 (no padding).
std::vector<std::uint8_t> three_datagram_frame() {
  FrameBuilder b;
  b.reset(MacAddress{0x02, 0, 0, 0, 0, 0x01});
  EXPECT_TRUE(b.add(Command::FPRD, 1, make_address(0x1000, 0x0130), 2).ok());
  EXPECT_TRUE(b.add(Command::LRW, 2, 0x10000, 6).ok());
  EXPECT_TRUE(b.add(Command::BRD, 3, 0, 1).ok());
  const ConstByteSpan f = b.finish();
  return std::vector<std::uint8_t>(f.begin(), f.end());
}

void set_ecat_length(std::vector<std::uint8_t>& f, std::size_t at, std::uint16_t length) {
  store_le16(f.data() + at, static_cast<std::uint16_t>((load_le16(f.data() + at) & 0xF800) | length));
}

Error parse_error(const std::vector<std::uint8_t>& f) {
  const auto r = FrameView::parse(ConstByteSpan(f.data(), f.size()));
  EXPECT_FALSE(r.ok());
  return r.ok() ? Error{} : r.error();
}

void expect_error(const Error& e, Errc code, const char* what, std::uint32_t d0, std::uint32_t d1) {
  EXPECT_EQ(e.code, code) << to_string(e.code);
  EXPECT_STREQ(e.what, what);
  EXPECT_EQ(e.detail0, d0) << e.what;
  EXPECT_EQ(e.detail1, d1) << e.what;
}

TEST(FrameErrors, ReferenceFrameParses) {
  const auto f = three_datagram_frame();
  const auto r = FrameView::parse(ConstByteSpan(f.data(), f.size()));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value().datagram_count(), 3U);
  EXPECT_EQ(r.value().header().ecat_end(), 61U);
  EXPECT_EQ(f.size(), 61U);
}

TEST(FrameErrors, ShortEthernetHeader) {
  const std::vector<std::uint8_t> f(13, 0xFF);
  expect_error(parse_error(f), Errc::truncated, "ethernet header", kFrameLevel, 0);
}

TEST(FrameErrors, OtherEtherTypeIsNotEtherCAT) {
  auto f = three_datagram_frame();
  store_be16(f.data() + 12, 0x0800);
  expect_error(parse_error(f), Errc::unsupported, "not EtherCAT", kFrameLevel, 12);
}

TEST(FrameErrors, VlanTagWithoutRoomForTheInnerType) {
  std::vector<std::uint8_t> f(16, 0);
  store_be16(f.data() + 12, kEtherTypeVlan);
  expect_error(parse_error(f), Errc::truncated, "vlan tag", kFrameLevel, 12);
}

TEST(FrameErrors, VlanTaggedOtherEtherType) {
  std::vector<std::uint8_t> f(60, 0);
  store_be16(f.data() + 12, kEtherTypeVlan);
  store_be16(f.data() + 16, 0x0806);
  expect_error(parse_error(f), Errc::unsupported, "not EtherCAT", kFrameLevel, 16);
}

TEST(FrameErrors, EtherCATHeaderCutOff) {
  auto f = three_datagram_frame();
  f.resize(15);
  expect_error(parse_error(f), Errc::truncated, "ecat header", kFrameLevel, 14);
}

TEST(FrameErrors, EtherCATTypeOtherThanDatagrams) {
  auto f = three_datagram_frame();
  f[15] = static_cast<std::uint8_t>((f[15] & 0x0F) | 0x40);  // type 4: network variables
  expect_error(parse_error(f), Errc::unsupported, "ecat type", kFrameLevel, 14);
}

TEST(FrameErrors, EtherCATLengthBeyondTheFrame) {
  auto f = three_datagram_frame();
  set_ecat_length(f, 14, static_cast<std::uint16_t>(f.size() - 16 + 1));
  expect_error(parse_error(f), Errc::truncated, "ecat length", kFrameLevel, 14);
}

TEST(FrameErrors, EtherCATLengthOfZero) {
  auto f = three_datagram_frame();
  set_ecat_length(f, 14, 0);
  expect_error(parse_error(f), Errc::truncated, "datagram header", 0, 16);
}

TEST(FrameErrors, EtherCATLengthEndingInsideTheSecondHeader) {
  auto f = three_datagram_frame();
  set_ecat_length(f, 14, 14 + 9);  // first datagram (14 bytes) + 9 of the second header
  expect_error(parse_error(f), Errc::truncated, "datagram header", 1, 30);
}

TEST(FrameErrors, DatagramLengthBeyondTheEtherCATLength) {
  auto f = three_datagram_frame();
  set_ecat_length(f, 48 + 6, 2);  // last datagram claims one byte more than is left
  expect_error(parse_error(f), Errc::truncated, "datagram length", 2, 54);
}

TEST(FrameErrors, DatagramLengthOfTheMaximumElevenBits) {
  auto f = three_datagram_frame();
  set_ecat_length(f, 16 + 6, 0x07FF);
  expect_error(parse_error(f), Errc::truncated, "datagram length", 0, 22);
}

TEST(FrameErrors, UnknownCommand) {
  auto f = three_datagram_frame();
  f[48] = 15;
  expect_error(parse_error(f), Errc::malformed, "datagram command", 2, 48);
  f[48] = 0xFF;
  expect_error(parse_error(f), Errc::malformed, "datagram command", 2, 48);
}

TEST(FrameErrors, MoreFollowsOnTheLastDatagram) {
  auto f = three_datagram_frame();
  f[48 + 7] |= 0x80;  // third datagram says another follows; none does
  expect_error(parse_error(f), Errc::truncated, "datagram header", 3, 61);
}

TEST(FrameErrors, EtherCATLengthLongerThanTheDatagrams) {
  auto f = three_datagram_frame();
  f.resize(63, 0);
  f[61] = 0x5A;  // not padding: padding is zero
  set_ecat_length(f, 14, static_cast<std::uint16_t>(61 - 16 + 2));  // two bytes no datagram uses
  expect_error(parse_error(f), Errc::malformed, "bytes after last datagram", 3, 61);
}

TEST(FrameErrors, MoreThan124Datagrams) {
  // 125 empty datagrams need 1500 bytes of payload: only a VLAN-sized frame with FCS holds them.
  std::vector<std::uint8_t> f(16 + 125 * 12, 0);
  store_be16(f.data() + 12, kEtherTypeEtherCAT);
  store_le16(f.data() + 14, static_cast<std::uint16_t>((125 * 12) | 0x1000));
  for (std::size_t i = 0; i < 125; ++i) store_le16(f.data() + 16 + i * 12 + 6, 0x8000);
  expect_error(parse_error(f), Errc::malformed, "datagram count", 124, static_cast<std::uint32_t>(16 + 124 * 12));
}

TEST(FrameErrors, MutableParseGivesTheSameErrors) {
  auto f = three_datagram_frame();
  f[30] = 200;
  const auto r = MutableFrameView::parse(ByteSpan(f.data(), f.size()));
  ASSERT_FALSE(r.ok());
  expect_error(r.error(), Errc::malformed, "datagram command", 1, 30);
}

}  // namespace
}  // namespace rescue::ecat
