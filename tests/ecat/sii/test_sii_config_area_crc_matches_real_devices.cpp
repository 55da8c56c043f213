// The config-area checksum (SII word 7): CRC-8, polynomial 0x07, initial value 0xFF, over bytes
// 0..13. Checked against the values real devices carry and against a hand-computed vector.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>

#include "ecat/sii/sii.hpp"

namespace rescue::ecat::sii {
namespace {

// 14 zero bytes from init 0xFF: a value computed independently (a bitwise Python loop) pins the
// polynomial, the initial value and the absence of reflection.
constexpr std::array<std::uint8_t, 14> kZeros{};
static_assert(config_area_crc(kZeros.data()) == 0x30, "CRC-8/0x07 init 0xFF of 14 zero bytes");

TEST(SiiConfigAreaCrc, EmptyInputIsTheInitialValue) { EXPECT_EQ(config_area_crc(kZeros.data(), 0), 0xFF); }

TEST(SiiConfigAreaCrc, MatchesTheChecksumEveryRealDeviceStores) {
  const char* names[] = {"ek1100.bin", "akd.bin", "el2828.bin"};
  const std::uint8_t stored[] = {0x46, 0x10, 0xE2};
  for (int i = 0; i < 3; ++i) {
    const std::string path = std::string(RESCUE_SHARED_DIR) + "/vectors/sii/" + names[i];
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) GTEST_SKIP() << "needs " << path << " (shared vectors absent)";
    std::array<std::uint8_t, 16> head{};
    const std::size_t n = std::fread(head.data(), 1, head.size(), f);
    std::fclose(f);
    ASSERT_EQ(n, head.size());
    EXPECT_EQ(head[14], stored[i]) << names[i];
    EXPECT_EQ(config_area_crc(head.data()), stored[i]) << names[i];
  }
}

TEST(SiiConfigAreaCrc, AnySingleBitFlipChangesTheChecksum) {
  std::array<std::uint8_t, 14> bytes{0x00, 0x0d, 0, 0, 0, 0, 0, 0, 0x34, 0x12, 0, 0, 0, 0};
  const std::uint8_t good = config_area_crc(bytes.data());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      bytes[i] = static_cast<std::uint8_t>(bytes[i] ^ (1U << bit));
      EXPECT_NE(config_area_crc(bytes.data()), good) << "byte " << i << " bit " << bit;
      bytes[i] = static_cast<std::uint8_t>(bytes[i] ^ (1U << bit));
    }
  }
}

}  // namespace
}  // namespace rescue::ecat::sii
