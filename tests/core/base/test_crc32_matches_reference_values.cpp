#include <gtest/gtest.h>

#include <cstring>

#include "core/base/crc32.hpp"

namespace rescue {
namespace {

ConstByteSpan text(const char* s) { return ConstByteSpan(reinterpret_cast<const std::uint8_t*>(s), std::strlen(s)); }

TEST(Crc32, MatchesTheStandardCheckValue) {
  EXPECT_EQ(crc32(text("123456789")), 0xCBF43926u);  // the CRC-32/ISO-HDLC check value
  EXPECT_EQ(crc32(text("")), 0x00000000u);
  EXPECT_EQ(crc32(text("The quick brown fox jumps over the lazy dog")), 0x414FA339u);
}

TEST(Crc32, IncrementalEqualsOneShotAndWorksAtCompileTime) {
  Crc32 c;
  c.update(text("12345"));
  c.update(text("6789"));
  EXPECT_EQ(c.value(), 0xCBF43926u);
  constexpr std::uint8_t bytes[] = {'a'};
  static_assert(crc32(ConstByteSpan(bytes, 1)) == 0xE8B7BE43u, "crc32(\"a\")");
}

TEST(Crc32, DetectsEverySingleBitFlip) {
  std::uint8_t data[64];
  for (std::size_t i = 0; i < sizeof data; ++i) data[i] = static_cast<std::uint8_t>(i * 7 + 3);
  const std::uint32_t good = crc32(ConstByteSpan(data, sizeof data));
  for (std::size_t bit = 0; bit < sizeof data * 8; ++bit) {
    data[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    EXPECT_NE(crc32(ConstByteSpan(data, sizeof data)), good) << bit;
    data[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
  }
}

}  // namespace
}  // namespace rescue
