#include <gtest/gtest.h>

#include "ecat/codec/frame.hpp"

namespace rescue::ecat {
namespace {

TEST(FrameBuilder, TwoDatagramsRoundTrip) {
  FrameBuilder b;
  b.reset(MacAddress{0x02, 0, 0, 0, 0, 1});
  const std::uint8_t payload[4] = {1, 2, 3, 4};
  auto s1 = b.add(Command::FPRD, 7, make_address(0x1000, 0x0130), 2);
  auto s2 = b.add(Command::LRW, 8, 0x00010000, 4, ConstByteSpan(payload), 0, 3);
  ASSERT_TRUE(s1.ok());
  ASSERT_TRUE(s2.ok());
  const ConstByteSpan frame = b.finish();
  EXPECT_EQ(frame.size(), kMinFrameSize);  // padded

  auto parsed = FrameView::parse(frame);
  ASSERT_TRUE(parsed.ok()) << parsed.error().what;
  ASSERT_EQ(parsed.value().datagram_count(), 2u);
  int i = 0;
  for (DatagramView d : parsed.value()) {
    if (i == 0) {
      EXPECT_EQ(d.command(), Command::FPRD);
      EXPECT_EQ(d.index(), 7);
      EXPECT_EQ(d.adp(), 0x1000);
      EXPECT_EQ(d.ado(), 0x0130);
      EXPECT_EQ(d.length(), 2);
      EXPECT_TRUE(d.more_follows());
      EXPECT_EQ(d.wkc(), 0);
    } else {
      EXPECT_EQ(d.command(), Command::LRW);
      EXPECT_EQ(d.address(), 0x00010000u);
      EXPECT_EQ(d.data()[3], 4);
      EXPECT_FALSE(d.more_follows());
      EXPECT_EQ(d.wkc(), 3);
    }
    ++i;
  }
}

TEST(FrameBuilder, RefusesDatagramThatDoesNotFit) {
  FrameBuilder b;
  ASSERT_TRUE(b.add(Command::LRD, 0, 0, static_cast<std::uint16_t>(kMaxDatagramDataLength)).ok());
  auto r = b.add(Command::NOP, 1, 0, 0);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::capacity_exceeded);
  EXPECT_EQ(b.finish().size(), kMaxFrameSize);
}

TEST(FrameView, MutableViewWritesWorkingCounterInPlace) {
  FrameBuilder b;
  ASSERT_TRUE(b.add(Command::BRD, 0, make_address(0, 0x0000), 2).ok());
  const ConstByteSpan built = b.finish();
  std::array<std::uint8_t, kMaxFrameSize> copy{};
  std::copy(built.begin(), built.end(), copy.begin());
  auto parsed = MutableFrameView::parse(ByteSpan(copy.data(), built.size()));
  ASSERT_TRUE(parsed.ok());
  for (MutableDatagramView d : parsed.value()) d.set_wkc(23);
  auto again = FrameView::parse(ConstByteSpan(copy.data(), built.size()));
  ASSERT_TRUE(again.ok());
  EXPECT_EQ((*again.value().begin()).wkc(), 23);
}

}  // namespace
}  // namespace rescue::ecat
