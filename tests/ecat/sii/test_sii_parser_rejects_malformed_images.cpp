// The SII parser takes untrusted bytes: truncated or inconsistent images are refused with an error
// that names the field and the offset, never read out of bounds (the fuzz target covers the rest).
#include <gtest/gtest.h>

#include <vector>

#include "core/base/endian.hpp"
#include "ecat/sii/sii.hpp"

namespace rescue::ecat::sii {
namespace {

// A minimal valid image: header with identity and a correct CRC, then the given categories.
struct ImageUnderTest {
  std::vector<std::uint8_t> bytes = std::vector<std::uint8_t>(kHeaderBytes, 0);
  ImageUnderTest() {
    store_le32(&bytes[2 * kVendorId], 0x1234);
    store_le16(&bytes[2 * kEepromSize], 0x000F);
    store_le16(&bytes[2 * kVersion], 1);
    seal();
  }
  void seal() { bytes[2 * kConfigChecksum] = config_area_crc(bytes.data()); }
  void category(std::uint16_t type, std::vector<std::uint8_t> data, int declared_words = -1) {
    const std::size_t at = bytes.size();
    bytes.resize(at + 4);
    store_le16(&bytes[at], type);
    const auto words = declared_words >= 0 ? static_cast<std::uint16_t>(declared_words) : static_cast<std::uint16_t>((data.size() + 1) / 2);
    store_le16(&bytes[at + 2], words);
    if (data.size() % 2 != 0) data.push_back(0);
    bytes.insert(bytes.end(), data.begin(), data.end());
  }
  void end() { bytes.insert(bytes.end(), {0xFF, 0xFF}); }
  Result<Sii> parse(ChecksumPolicy policy = ChecksumPolicy::require) const {
    return Sii::parse(ConstByteSpan(bytes.data(), bytes.size()), policy);
  }
};

void expect_error(const Result<Sii>& r, Errc code, const char* what) {
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, code);
  EXPECT_STREQ(r.error().what, what);
}

TEST(SiiParserRejects, ImageShorterThanTheHeader) {
  std::vector<std::uint8_t> bytes(100, 0);
  auto r = Sii::parse(ConstByteSpan(bytes.data(), bytes.size()));
  expect_error(r, Errc::truncated, "sii header");
  EXPECT_EQ(r.error().detail1, 100u);
}

TEST(SiiParserRejects, WrongConfigAreaChecksumUnlessIgnored) {
  ImageUnderTest img;
  img.bytes[2 * kConfigChecksum] ^= 0x01;
  expect_error(img.parse(), Errc::checksum, "sii config area crc");
  auto lenient = img.parse(ChecksumPolicy::ignore);
  ASSERT_TRUE(lenient.ok());
  EXPECT_FALSE(lenient.value().config.checksum_ok());
  EXPECT_EQ(lenient.value().identity.vendor_id, 0x1234u);
}

TEST(SiiParserAccepts, HeaderOnlyAndImageEndingWithoutEndMarker) {
  ImageUnderTest img;
  auto r = img.parse();
  ASSERT_TRUE(r.ok()) << r.error().what;
  EXPECT_EQ(r.value().category_count, 0u);
  EXPECT_EQ(r.value().eeprom_size_bytes, 2048u);
  EXPECT_EQ(r.value().name(), "");
}

TEST(SiiParserRejects, CategoryLongerThanTheImage) {
  ImageUnderTest img;
  img.category(kCategoryStrings, {1, 2, 'a', 'b'}, 40);
  expect_error(img.parse(), Errc::truncated, "sii category size");
}

TEST(SiiParserRejects, CategoryHeaderCutInHalf) {
  ImageUnderTest img;
  img.bytes.insert(img.bytes.end(), {0x0A, 0x00});
  auto r = img.parse();
  expect_error(r, Errc::truncated, "sii category header");
  EXPECT_EQ(r.error().detail0, kCategoryStrings);
  EXPECT_EQ(r.error().detail1, kHeaderBytes);
}

TEST(SiiParserRejects, StringRunningPastItsCategory) {
  ImageUnderTest img;
  img.category(kCategoryStrings, {2, 1, 'a', 9, 'b', 'c'});
  img.end();
  expect_error(img.parse(), Errc::truncated, "sii string text");
}

TEST(SiiParserRejects, StringCountLargerThanTheStrings) {
  ImageUnderTest img;
  img.category(kCategoryStrings, {4, 1, 'a', 1, 'b'});  // the pad byte reads as a 3rd, empty string
  img.end();
  expect_error(img.parse(), Errc::truncated, "sii string length");
}

TEST(SiiParserRejects, GeneralCategoryShorterThan32Bytes) {
  ImageUnderTest img;
  img.category(kCategoryGeneral, std::vector<std::uint8_t>(20, 0));
  img.end();
  expect_error(img.parse(), Errc::truncated, "sii general category");
}

TEST(SiiParserRejects, SyncManagerCategoryNotWholeRecords) {
  ImageUnderTest img;
  img.category(kCategorySyncManager, std::vector<std::uint8_t>(10, 0));
  img.end();
  expect_error(img.parse(), Errc::malformed, "sii sync manager category size");
}

TEST(SiiParserRejects, PdoAnnouncingMoreEntriesThanItHolds) {
  ImageUnderTest img;
  // index 0x1A00, 3 entries, SM 3, but only one 8-byte entry follows.
  img.category(kCategoryTxPdo, {0x00, 0x1A, 3, 3, 0, 0, 0, 0, 0x41, 0x60, 0, 0, 6, 16, 0, 0});
  img.end();
  expect_error(img.parse(), Errc::truncated, "sii pdo entries");
}

TEST(SiiParserRejects, PdoHeaderCutShort) {
  ImageUnderTest img;
  img.category(kCategoryRxPdo, {0x00, 0x16, 0, 2});
  img.end();
  expect_error(img.parse(), Errc::truncated, "sii pdo header");
}

TEST(SiiParserRejects, DcCategoryNotWholeRecords) {
  ImageUnderTest img;
  img.category(kCategoryDc, std::vector<std::uint8_t>(30, 0));
  img.end();
  expect_error(img.parse(), Errc::malformed, "sii dc category size");
}

TEST(SiiParserRejects, MoreSyncManagersThanAnEscHas) {
  ImageUnderTest img;
  img.category(kCategorySyncManager, std::vector<std::uint8_t>(8 * (kMaxSyncManagers + 1), 0));
  img.end();
  expect_error(img.parse(), Errc::capacity_exceeded, "sii sync managers");
}

TEST(SiiParserIgnores, UnknownCategoriesAndStringIndicesPastTheTable) {
  ImageUnderTest img;
  img.category(0x0800, {1, 2, 3, 4});
  img.category(kCategoryStrings, {1, 2, 'h', 'i'});
  std::vector<std::uint8_t> general(32, 0);
  general[3] = 1;  // name
  general[2] = 7;  // order: no such string
  img.category(kCategoryGeneral, general);
  img.end();
  img.bytes.insert(img.bytes.end(), {0x0A, 0x00, 0x55, 0x55});  // after the end marker: not read
  auto r = img.parse();
  ASSERT_TRUE(r.ok()) << r.error().what;
  EXPECT_EQ(r.value().name(), "hi");
  EXPECT_EQ(r.value().order(), "");
  EXPECT_EQ(r.value().string(0), "");
  EXPECT_EQ(r.value().category_count, 3u);
}

}  // namespace
}  // namespace rescue::ecat::sii
