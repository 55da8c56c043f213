// The SII cache at bring-up (docs/master.md "SII cache"): on the simulated robot (virtual time), a
// second robot of the same devices is identified from the cache after each slave's first 32 EEPROM
// bytes, in a fraction of the frames; a cached image whose serial number, revision or configuration
// area differs from the slave's is never used (that slave is read whole, and identified as it is);
// a cache file whose checksum fails is refused whole (every slave read whole).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/base/crc32.hpp"
#include "core/base/endian.hpp"
#include "drivers/joint/device_identity.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/sii/sii.hpp"
#include "ecat/sii/sii_cache.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

struct Outcome {
  bool up{false};
  std::uint32_t cache_hits{0};
  std::uint32_t sii_frames{0};
  std::vector<std::uint32_t> serials;  // as identified, by position
};

Outcome bring_up(SiiCache* cache) {
  auto rig = std::make_unique<SimulatedRobotRig>();
  EXPECT_TRUE(rig->built.ok());
  MasterOptions options = testing::fast_options();
  options.sii_cache = cache;
  Outcome out;
  out.up = rig->bus.bring_up(options).ok();
  EXPECT_TRUE(out.up) << testing::describe_master_failure(rig->bus.master());
  const BringUpReport& report = rig->bus.master().report();
  out.cache_hits = report.sii.cache_hits;
  out.sii_frames = report.sii.frames;
  for (const FoundSlave& f : report.found.span()) out.serials.push_back(f.serial_number);
  return out;
}

// The cache's file form, one entry's bytes changed (and, when `reseal`, every CRC made right again).
struct CacheFile {
  std::vector<std::uint8_t> bytes;
  explicit CacheFile(const SiiCache& cache) : bytes(kSiiCacheFileMax) {
    const Result<std::size_t> n = cache.encode(ByteSpan(bytes.data(), bytes.size()));
    EXPECT_TRUE(n.ok());
    bytes.resize(n.ok() ? n.value() : 0);
  }
  // Offset of entry `i`'s image.
  std::size_t image_at(std::size_t i) const {
    std::size_t at = 12;
    for (std::size_t k = 0; k < i; ++k) at += 2 + load_le16(&bytes[at]) + 4;
    return at + 2;
  }
  std::size_t image_size(std::size_t i) const { return load_le16(&bytes[image_at(i) - 2]); }
  void set_u32(std::size_t entry, std::size_t offset, std::uint32_t v) { store_le32(&bytes[image_at(entry) + offset], v); }
  void set_u16(std::size_t entry, std::size_t offset, std::uint16_t v) { store_le16(&bytes[image_at(entry) + offset], v); }
  void reseal_config_area(std::size_t entry) {
    std::uint8_t* image = &bytes[image_at(entry)];
    image[2 * sii::kConfigChecksum] = sii::config_area_crc(image);
  }
  void reseal() {
    for (std::size_t i = 0; i < load_le32(&bytes[8]); ++i) {
      const std::size_t at = image_at(i);
      store_le32(&bytes[at + image_size(i)], crc32(ConstByteSpan(&bytes[at], image_size(i))));
    }
    store_le32(&bytes[bytes.size() - 4], crc32(ConstByteSpan(bytes.data(), bytes.size() - 4)));
  }
  Status load(SiiCache& cache) const { return cache.decode(ConstByteSpan(bytes.data(), bytes.size())); }
};

TEST(SiiCacheAtBringUp, ASecondRobotOfTheSameDevicesIsIdentifiedFromTheCache) {
  SiiCache cache;
  const Outcome first = bring_up(&cache);
  EXPECT_EQ(first.cache_hits, 0U);
  EXPECT_EQ(cache.size(), kSlaveCount) << "every image read whole is taken in";
  EXPECT_TRUE(cache.changed());

  const Outcome second = bring_up(&cache);
  EXPECT_EQ(second.cache_hits, kSlaveCount);
  EXPECT_EQ(second.serials, first.serials);
  // 4 EEPROM reads (32 bytes) per slave instead of the whole image.
  EXPECT_LT(second.sii_frames * 10, first.sii_frames) << second.sii_frames << " vs " << first.sii_frames;
}

TEST(SiiCacheAtBringUp, AnImageOfAnotherSerialRevisionOrConfigurationIsNeverUsed) {
  SiiCache cache;
  ASSERT_TRUE(bring_up(&cache).up);
  CacheFile file(cache);
  // Entries are in position order. Position 5: another unit (serial), 6: another revision, 7: its
  // configuration area changed (station alias, CRC-8 made right), each as a cached image would be
  // of a device that was replaced or re-flashed since.
  file.set_u32(5, 2 * sii::kSerial, drivers::serial_number_of(5) + 1000);
  file.set_u32(6, 2 * sii::kRevision, drivers::kJointDriveIdentity.revision + 1);
  file.set_u16(7, 2 * sii::kStationAlias, 0x7777);
  file.reseal_config_area(7);
  file.reseal();
  SiiCache changed;
  ASSERT_TRUE(file.load(changed).ok());

  const Outcome out = bring_up(&changed);
  EXPECT_EQ(out.cache_hits, kSlaveCount - 3);
  ASSERT_EQ(out.serials.size(), kSlaveCount);
  for (std::size_t p = 0; p < kSlaveCount; ++p) EXPECT_EQ(out.serials[p], drivers::serial_number_of(p)) << p;
}

TEST(SiiCacheAtBringUp, ACacheFileWhoseChecksumFailsIsRefusedWhole) {
  SiiCache cache;
  ASSERT_TRUE(bring_up(&cache).up);
  CacheFile file(cache);
  file.bytes[file.image_at(3) + file.image_size(3) - 10] ^= 0x01U;  // one bit of one image, the CRC-32s left as they were
  SiiCache damaged;
  EXPECT_FALSE(file.load(damaged).ok());
  EXPECT_EQ(damaged.size(), 0U);
  const Outcome out = bring_up(&damaged);
  EXPECT_EQ(out.cache_hits, 0U);
  EXPECT_EQ(damaged.size(), kSlaveCount) << "the images read whole are taken in again";
}

}  // namespace
}  // namespace rescue::ecat
