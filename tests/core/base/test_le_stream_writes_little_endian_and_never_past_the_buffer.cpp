// core/base/le_stream.hpp: the writer lays every field down little-endian, byte by byte; a write
// or read that does not fit touches nothing, fails the stream and every later access; no heap.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "core/base/le_stream.hpp"
#include "core/memory/heap_guard.hpp"

namespace rescue {
namespace {

TEST(LeStream, WritesEveryWidthLittleEndianAndReadsItBack) {
  std::array<std::uint8_t, 32> buf{};
  LeWriter w{ByteSpan(buf)};
  w.u8(0x01);
  w.u16(0x0302);
  w.u32(0x07060504U);
  w.u64(0x0F0E0D0C0B0A0908ULL);
  w.zeros(2);
  w.chars("ab", 2);
  const std::uint8_t raw[] = {0xAA, 0xBB};
  w.bytes(raw, 2);
  w.f64(-1.5);
  ASSERT_TRUE(w.ok());
  EXPECT_EQ(w.size(), 29U);
  for (std::size_t i = 0; i < 15; ++i) EXPECT_EQ(buf[i], i + 1) << i;
  EXPECT_EQ(buf[15], 0);
  EXPECT_EQ(buf[16], 0);
  EXPECT_EQ(buf[17], 'a');
  EXPECT_EQ(buf[19], 0xAA);
  EXPECT_EQ(buf[28], 0xBF);  // -1.5 = 0xBFF8000000000000
  EXPECT_EQ(buf[27], 0xF8);

  LeReader r{ConstByteSpan(buf.data(), w.size())};
  EXPECT_EQ(r.u8(), 0x01);
  EXPECT_EQ(r.u16(), 0x0302);
  EXPECT_EQ(r.u32(), 0x07060504U);
  EXPECT_EQ(r.u64(), 0x0F0E0D0C0B0A0908ULL);
  EXPECT_TRUE(r.zeros(2));
  std::array<char, 2> text{};
  r.chars(text.data(), 2);
  EXPECT_EQ(text[1], 'b');
  EXPECT_FALSE(r.zeros(2));  // 0xAA 0xBB
  EXPECT_EQ(r.f64(), -1.5);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.size(), 29U);
  EXPECT_EQ(r.peek(2), 0x03);  // looking back or ahead moves nothing and never fails
  EXPECT_EQ(r.peek(29), 0);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.size(), 29U);
}

TEST(LeStream, PatchesAtAnOffsetWithoutMovingOn) {
  std::array<std::uint8_t, 8> buf{};
  LeWriter w{ByteSpan(buf)};
  w.u32(0);
  w.skip(2);
  w.u32_at(0, 0xDDCCBBAAU);
  w.u16_at(6, 0x1122);
  EXPECT_TRUE(w.ok());
  EXPECT_EQ(w.size(), 6U);
  EXPECT_EQ(buf[0], 0xAA);
  EXPECT_EQ(buf[3], 0xDD);
  EXPECT_EQ(buf[6], 0x22);
  EXPECT_EQ(buf[7], 0x11);
  w.u16_at(7, 0xFFFF);  // one byte past the end
  EXPECT_FALSE(w.ok());
  EXPECT_EQ(buf[7], 0x11);
}

TEST(LeStream, AWriteThatDoesNotFitTouchesNothingAndFailsForGood) {
  std::array<std::uint8_t, 8> buf{};
  buf.fill(0x55);
  LeWriter w{ByteSpan(buf.data(), 6)};
  w.u32(0x01020304U);
  w.u32(0xFFFFFFFFU);  // 2 bytes left: refused whole
  EXPECT_FALSE(w.ok());
  EXPECT_EQ(w.size(), 4U);
  EXPECT_EQ(buf[4], 0x55);
  w.u8(0xFF);  // would fit, but the stream has failed
  EXPECT_EQ(buf[4], 0x55);
  EXPECT_EQ(w.size(), 4U);
  EXPECT_EQ(buf[6], 0x55);  // never past the span
}

TEST(LeStream, AReadPastTheEndGivesZeroAndFailsForGood) {
  const std::array<std::uint8_t, 5> buf{{1, 2, 3, 4, 5}};
  LeReader r{ConstByteSpan(buf)};
  EXPECT_EQ(r.u32(), 0x04030201U);
  EXPECT_EQ(r.u16(), 0);  // one byte left
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.u8(), 0);  // would fit, but the stream has failed
  EXPECT_EQ(r.size(), 4U);
  std::array<char, 3> text{{'x', 'x', 'x'}};
  r.chars(text.data(), 3);
  EXPECT_EQ(text[0], '\0');
}

TEST(LeStream, NeverAllocates) {
  std::array<std::uint8_t, 64> buf{};
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);
  LeWriter w{ByteSpan(buf)};
  for (int i = 0; i < 8; ++i) w.u64(0x0102030405060708ULL);
  w.u8(1);
  LeReader r{ConstByteSpan(buf)};
  while (r.ok()) (void)r.u32();
  const HeapGuardCounters during = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_FALSE(w.ok());
  EXPECT_EQ(during.allocations, 0U);
}

}  // namespace
}  // namespace rescue
