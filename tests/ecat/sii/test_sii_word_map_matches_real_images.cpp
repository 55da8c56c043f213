// The SII word addresses in ecat/codec/registers.hpp read the right fields of real EEPROM images
// (../shared/vectors/sii): identity, mailbox layout, protocols, size, the configuration checksum and
// the first category.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"
#include "tests/support/shared_sii_images.hpp"

namespace rescue::ecat {
namespace {

std::vector<std::uint8_t> load_image(const char* name) { return test::read_shared_sii(name); }

bool shared_present() {
  std::ifstream probe(std::string(RESCUE_SHARED_DIR) + "/vectors/sii/ek1100.bin");
  return probe.good();
}

std::uint16_t word(const std::vector<std::uint8_t>& image, std::uint16_t address) {
  return load_le16(image.data() + 2U * address);
}
std::uint32_t dword(const std::vector<std::uint8_t>& image, std::uint16_t address) {
  return load_le32(image.data() + 2U * address);
}

// CRC-8, polynomial x^8 + x^2 + x + 1, initial 0xFF, over words 0..6 (ETG.1000.6).
std::uint8_t sii_checksum(const std::vector<std::uint8_t>& image) {
  std::uint8_t crc = 0xFF;
  for (std::size_t i = 0; i < 14; ++i) {
    crc ^= image[i];
    for (int bit = 0; bit < 8; ++bit) {
      crc = static_cast<std::uint8_t>((crc & 0x80) != 0 ? (crc << 1) ^ 0x07 : crc << 1);
    }
  }
  return crc;
}

class SiiImages : public testing::Test {
 protected:
  void SetUp() override {
    if (!shared_present()) GTEST_SKIP() << "no SII images: " << RESCUE_SHARED_DIR << "/vectors/sii is absent";
  }
};

TEST_F(SiiImages, Ek1100IdentityAndNoMailbox) {
  const auto image = load_image("ek1100.bin");
  ASSERT_EQ(image.size(), 2048U);
  EXPECT_EQ(dword(image, sii::kVendorId), 0x00000002U);     // Beckhoff
  EXPECT_EQ(dword(image, sii::kProductCode), 0x044C2C52U);  // EK1100
  EXPECT_EQ(word(image, sii::kMailboxProtocols), 0U);
  EXPECT_EQ(word(image, sii::kStdRxMailboxSize), 0U);
  EXPECT_EQ(word(image, sii::kEepromSize), 15U);  // 16 kbit = 2048 bytes
  EXPECT_EQ(word(image, sii::kVersion), 1U);
  EXPECT_EQ(word(image, sii::kFirstCategory), sii::kCategoryStrings);
  EXPECT_EQ(word(image, sii::kConfigChecksum) & 0xFF, sii_checksum(image));
}

TEST_F(SiiImages, AkdMailboxLayoutAndProtocols) {
  const auto image = load_image("akd.bin");
  ASSERT_EQ(image.size(), 2048U);
  EXPECT_EQ(dword(image, sii::kVendorId), 0x0000006AU);  // Kollmorgen
  EXPECT_EQ(word(image, sii::kBootRxMailboxOffset), 0x1800);
  EXPECT_EQ(word(image, sii::kBootRxMailboxSize), 0x0400);
  EXPECT_EQ(word(image, sii::kBootTxMailboxOffset), 0x1C00);
  EXPECT_EQ(word(image, sii::kBootTxMailboxSize), 0x0400);
  EXPECT_EQ(word(image, sii::kStdRxMailboxOffset), 0x1800);
  EXPECT_EQ(word(image, sii::kStdRxMailboxSize), 0x0400);
  EXPECT_EQ(word(image, sii::kStdTxMailboxOffset), 0x1C00);
  EXPECT_EQ(word(image, sii::kStdTxMailboxSize), 0x0400);
  EXPECT_EQ(word(image, sii::kMailboxProtocols), sii::kMailboxEoE | sii::kMailboxCoE | sii::kMailboxFoE);
  EXPECT_EQ(word(image, sii::kConfigChecksum) & 0xFF, sii_checksum(image));
}

TEST_F(SiiImages, El2828IdentityAndChecksum) {
  const auto image = load_image("el2828.bin");
  ASSERT_EQ(image.size(), 2048U);
  EXPECT_EQ(dword(image, sii::kVendorId), 0x00000002U);
  EXPECT_EQ(dword(image, sii::kProductCode), 0x0B0C3052U);  // EL2828
  EXPECT_EQ(word(image, sii::kConfigChecksum) & 0xFF, sii_checksum(image));
}

}  // namespace
}  // namespace rescue::ecat
