// The SII cache's file form (ecat/sii/sii_cache.hpp) read back exactly, and refused whole when any
// byte is missing or wrong (the cache is then empty: every slave is read whole); what the cache
// takes in: complete images with a serial number that parse with their configuration CRC.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "core/base/endian.hpp"
#include "drivers/sim/devices/joint_drive_sii.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/sii/sii.hpp"
#include "ecat/sii/sii_cache.hpp"

namespace rescue::ecat {
namespace {

// The simulated joint drive's SII at `position` as the reader leaves it: up to its end marker.
SiiImage drive_image(std::size_t position) {
  const Result<drivers::SiiImage> built = drivers::build_joint_drive_sii(position);
  EXPECT_TRUE(built.ok());
  SiiImage image;
  const Result<sii::Sii> parsed = sii::Sii::parse(ConstByteSpan(built.value().data(), built.value().size()));
  EXPECT_TRUE(parsed.ok());
  const std::size_t size = parsed.ok() ? parsed.value().end_offset : 0;
  EXPECT_LE(size, kSiiImageCapacity);
  std::memcpy(image.bytes.data(), built.value().data(), size);
  image.size = static_cast<std::uint16_t>(size);
  image.complete = true;
  return image;
}

std::vector<std::uint8_t> encode(const SiiCache& cache) {
  std::vector<std::uint8_t> out(kSiiCacheFileMax);
  const Result<std::size_t> n = cache.encode(ByteSpan(out.data(), out.size()));
  EXPECT_TRUE(n.ok());
  out.resize(n.ok() ? n.value() : 0);
  return out;
}

TEST(SiiCacheFile, ReadsBackExactlyAndFindsEachImageByItsFirst32Bytes) {
  SiiCache cache;
  for (std::size_t p : {1, 2, 5}) ASSERT_TRUE(cache.remember(drive_image(p)));
  const std::vector<std::uint8_t> file = encode(cache);
  SiiCache back;
  ASSERT_TRUE(back.decode(ConstByteSpan(file.data(), file.size())).ok());
  EXPECT_FALSE(back.changed());
  EXPECT_EQ(back.size(), 3U);
  EXPECT_EQ(encode(back), file);
  for (std::size_t p : {1, 2, 5}) {
    const SiiImage image = drive_image(p);
    const SiiImage* hit = back.find(ConstByteSpan(image.bytes.data(), kSiiIdentityBytes));
    ASSERT_NE(hit, nullptr) << p;
    ASSERT_EQ(hit->size, image.size);
    EXPECT_EQ(std::memcmp(hit->bytes.data(), image.bytes.data(), image.size), 0);
  }
  EXPECT_EQ(back.find(ConstByteSpan(drive_image(7).bytes.data(), kSiiIdentityBytes)), nullptr);
}

TEST(SiiCacheFile, RefusesEveryTruncationAndEveryFlippedByteWhole) {
  SiiCache cache;
  for (std::size_t p : {1, 2}) ASSERT_TRUE(cache.remember(drive_image(p)));
  const std::vector<std::uint8_t> file = encode(cache);
  for (std::size_t n = 0; n < file.size(); ++n) {
    SiiCache back;
    EXPECT_FALSE(back.decode(ConstByteSpan(file.data(), n)).ok()) << n;
    EXPECT_EQ(back.size(), 0U);
  }
  for (std::size_t i = 0; i < file.size(); ++i) {
    std::vector<std::uint8_t> bad = file;
    bad[i] ^= 0x10U;
    SiiCache back;
    EXPECT_FALSE(back.decode(ConstByteSpan(bad.data(), bad.size())).ok()) << i;
    EXPECT_EQ(back.size(), 0U);
  }
  std::vector<std::uint8_t> longer = file;
  longer.insert(longer.end() - 4, 0);
  SiiCache back;
  EXPECT_FALSE(back.decode(ConstByteSpan(longer.data(), longer.size())).ok());
}

TEST(SiiCacheFile, TakesInOnlyCompleteImagesWithASerialThatParse) {
  SiiCache cache;
  SiiImage no_serial = drive_image(1);
  store_le32(no_serial.bytes.data() + 2 * sii::kSerial, 0);
  EXPECT_FALSE(cache.remember(no_serial)) << "serial 0 cannot tell units apart";
  EXPECT_EQ(cache.find(ConstByteSpan(no_serial.bytes.data(), kSiiIdentityBytes)), nullptr);
  SiiImage bad_crc = drive_image(1);
  bad_crc.bytes[2 * sii::kConfigChecksum] ^= 0xFFU;
  EXPECT_FALSE(cache.remember(bad_crc));
  SiiImage incomplete = drive_image(1);
  incomplete.complete = false;
  EXPECT_FALSE(cache.remember(incomplete));
  SiiImage truncated = drive_image(1);
  truncated.truncated = true;
  EXPECT_FALSE(cache.remember(truncated));
  EXPECT_EQ(cache.size(), 0U);
  EXPECT_FALSE(cache.changed());

  // The same device again: one entry; its image changed (same identity): replaced.
  EXPECT_TRUE(cache.remember(drive_image(1)));
  EXPECT_TRUE(cache.remember(drive_image(1)));
  EXPECT_EQ(cache.size(), 1U);
  SiiImage realiased = drive_image(1);
  store_le16(realiased.bytes.data() + 2 * sii::kStationAlias, 0x4242);
  realiased.bytes[2 * sii::kConfigChecksum] = sii::config_area_crc(realiased.bytes.data());
  EXPECT_TRUE(cache.remember(realiased));
  EXPECT_EQ(cache.size(), 1U);
  EXPECT_NE(cache.find(ConstByteSpan(realiased.bytes.data(), kSiiIdentityBytes)), nullptr);
  EXPECT_EQ(cache.find(ConstByteSpan(drive_image(1).bytes.data(), kSiiIdentityBytes)), nullptr);
}

}  // namespace
}  // namespace rescue::ecat
