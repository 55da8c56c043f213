#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <fstream>
#include <string>

#include "core/base/endian.hpp"
#include "drivers/sim/devices/junction_device.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

TEST(JunctionSii, HeaderCarriesIdentityAndValidChecksum) {
  const JunctionDevice junction(1);
  const ConstByteSpan sii = junction.sii_image();
  ASSERT_GE(sii.size(), 128u);
  const std::uint8_t* p = sii.data();
  EXPECT_EQ(load_le16(p + 2 * ecat::sii::kConfigChecksum) & 0xFF, sii_config_crc(ConstByteSpan(p, 14)));
  EXPECT_EQ(load_le32(p + 2 * ecat::sii::kVendorId), kJunctionIdentity.vendor_id);
  EXPECT_EQ(load_le32(p + 2 * ecat::sii::kProductCode), kJunctionIdentity.product_code);
  EXPECT_EQ(load_le32(p + 2 * ecat::sii::kSerial), serial_number_of(1));
  EXPECT_EQ(load_le16(p + 2 * ecat::sii::kStationAlias), 0x1001);
  EXPECT_EQ(load_le16(p + 2 * ecat::sii::kStdRxMailboxSize), 0u);  // no mailbox
}

TEST(JunctionSii, ChecksumAlgorithmMatchesRealEeproms) {
  // The CRC real devices carry in word 7 (images read from an EK1100, an AKD and an EL2828).
  for (const char* file : {"ek1100.bin", "akd.bin", "el2828.bin"}) {
    const std::string path = std::string(RESCUE_SHARED_DIR) + "/vectors/sii/" + file;
    std::ifstream in(path, std::ios::binary);
    if (!in) GTEST_SKIP() << "real SII images not found at " << path << " (../shared/vectors is not in this checkout)";
    std::array<std::uint8_t, 16> head{};
    in.read(reinterpret_cast<char*>(head.data()), head.size());
    ASSERT_TRUE(in.good()) << path;
    EXPECT_EQ(sii_config_crc(ConstByteSpan(head.data(), 14)), head[14]) << file;
  }
}

TEST(JunctionSii, CategoriesNameTheDevice) {
  const JunctionDevice junction(0);
  const ConstByteSpan sii = junction.sii_image();
  std::size_t at = 2 * ecat::sii::kFirstCategory;
  bool found_name = false;
  bool found_general = false;
  bool found_end = false;
  while (at + 2 <= sii.size()) {
    const std::uint16_t type = load_le16(sii.data() + at);
    if (type == ecat::sii::kCategoryEnd) {
      found_end = true;
      break;
    }
    ASSERT_LE(at + 4, sii.size());
    const std::size_t bytes = 2U * load_le16(sii.data() + at + 2);
    ASSERT_LE(at + 4 + bytes, sii.size());
    if (type == ecat::sii::kCategoryStrings) {
      ASSERT_EQ(sii[at + 4], 1);
      const std::size_t n = sii[at + 5];
      found_name = n == 7 && std::memcmp(sii.data() + at + 6, "RM-JCT4", 7) == 0;
    }
    if (type == ecat::sii::kCategoryGeneral) found_general = sii[at + 4 + 3] == 1;
    at += 4 + bytes;
  }
  EXPECT_TRUE(found_name);
  EXPECT_TRUE(found_general);
  EXPECT_TRUE(found_end);
}

}  // namespace
}  // namespace rescue::drivers
