// Mailbox header (6 bytes): every field survives encode -> decode, the length is checked against
// the buffer, and error replies carry their detail code.
#include <gtest/gtest.h>

#include <array>

#include "ecat/mailbox/mailbox.hpp"

namespace rescue::ecat::mbx {
namespace {

TEST(MailboxHeader, EveryFieldRoundTrips) {
  std::array<std::uint8_t, 32> buf{};
  Header h;
  h.length = 10;
  h.address = 0x1003;
  h.channel = 0x2A;
  h.priority = 3;
  h.type = Type::coe;
  h.counter = 5;
  ASSERT_TRUE(encode_header(ByteSpan(buf), h).ok());
  EXPECT_EQ(buf[0], 10);
  EXPECT_EQ(buf[1], 0);
  EXPECT_EQ(buf[2], 0x03);
  EXPECT_EQ(buf[3], 0x10);
  EXPECT_EQ(buf[4], 0x2A | 0xC0);
  EXPECT_EQ(buf[5], 0x53);
  auto m = decode(ConstByteSpan(buf));
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m.value().header.length, 10);
  EXPECT_EQ(m.value().header.address, 0x1003);
  EXPECT_EQ(m.value().header.channel, 0x2A);
  EXPECT_EQ(m.value().header.priority, 3);
  EXPECT_EQ(m.value().header.type, Type::coe);
  EXPECT_EQ(m.value().header.counter, 5);
  EXPECT_EQ(m.value().data.size(), 10u);
  EXPECT_EQ(m.value().data.data(), buf.data() + kHeaderSize);
}

TEST(MailboxHeader, DecodeRefusesLengthPastTheBuffer) {
  std::array<std::uint8_t, 16> buf{};
  buf[0] = 11;  // 6 + 11 > 16
  auto m = decode(ConstByteSpan(buf));
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error().code, Errc::truncated);
  EXPECT_STREQ(m.error().what, "mailbox length");
  EXPECT_EQ(m.error().detail0, 11u);
  EXPECT_EQ(m.error().detail1, 10u);
  buf[0] = 10;
  EXPECT_TRUE(decode(ConstByteSpan(buf)).ok());
}

TEST(MailboxHeader, DecodeRefusesFewerThanSixBytes) {
  std::array<std::uint8_t, 5> buf{};
  auto m = decode(ConstByteSpan(buf));
  ASSERT_FALSE(m.ok());
  EXPECT_STREQ(m.error().what, "mailbox header");
}

TEST(MailboxHeader, EncodeRefusesOutOfRangeFieldsAndShortBuffers) {
  std::array<std::uint8_t, 16> buf{};
  Header h;
  h.counter = 8;
  EXPECT_EQ(encode_header(ByteSpan(buf), h).error().code, Errc::invalid_argument);
  h.counter = 1;
  h.channel = 64;
  EXPECT_EQ(encode_header(ByteSpan(buf), h).error().code, Errc::invalid_argument);
  h.channel = 0;
  h.length = 11;
  EXPECT_EQ(encode_header(ByteSpan(buf), h).error().code, Errc::capacity_exceeded);
}

TEST(MailboxHeader, CounterCyclesOneToSevenSkippingZero) {
  std::uint8_t c = 0;
  std::array<std::uint8_t, 9> seen{};
  for (auto& s : seen) {
    c = next_counter(c);
    s = c;
  }
  EXPECT_EQ(seen, (std::array<std::uint8_t, 9>{1, 2, 3, 4, 5, 6, 7, 1, 2}));
}

TEST(MailboxErrorReply, CarriesItsDetailCode) {
  std::array<std::uint8_t, 16> buf{};
  auto n = encode_error_reply(ByteSpan(buf), 0x1005, error_code::kUnsupportedProtocol);
  ASSERT_TRUE(n.ok());
  EXPECT_EQ(n.value(), 10u);
  auto m = decode(ConstByteSpan(buf.data(), n.value()));
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m.value().header.type, Type::error);
  EXPECT_EQ(m.value().header.address, 0x1005);
  auto detail = decode_error_reply(m.value());
  ASSERT_TRUE(detail.ok());
  EXPECT_EQ(detail.value(), error_code::kUnsupportedProtocol);
  EXPECT_STREQ(explain_error_code(detail.value()), "mailbox protocol not supported");
}

}  // namespace
}  // namespace rescue::ecat::mbx
