// A cache of SII images as the reader reads them (what the master uses: sii_reader.hpp), keyed by
// what the master always reads from every slave first: the first 32 bytes of its EEPROM (words
// 0..15: the configuration area with its CRC-8 in word 7, then vendor id, product code, revision and
// serial number). A slave whose first 32 bytes equal a cached
// image's, byte for byte, is that device with that EEPROM: the reader takes the rest of the image
// from the cache instead of reading it at 500 us per 4 bytes (read_sii_images, sii_reader.hpp).
//
// A changed device never gets a stale image: another unit has another serial, a re-flashed EEPROM
// another revision or configuration area, and those bytes are read from the slave every time.
// Images with serial number 0 (a device that does not tell its units apart) are never cached.
// Only images that parse with their configuration CRC checked are taken in.
//
// The file form (encode/decode; the firmware keeps it in its state directory, docs/master.md),
// little-endian, byte by byte:
//   magic "RMSIIC01" (8 bytes), u32 entry count
//   per entry: u16 image size, the image bytes, u32 CRC-32 of those bytes
//   u32 CRC-32 of everything before it
// decode() takes untrusted bytes: every length is checked, a file that fails any check is refused
// whole (the cache stays empty: every slave is read in full, nothing is lost but time).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/sii/sii_reader.hpp"

namespace rescue::ecat {

constexpr std::size_t kSiiCacheCapacity = 32;
constexpr std::size_t kSiiCacheFileMax = 16 + kSiiCacheCapacity * (2 + kSiiImageCapacity + 4) + 4;

class SiiCache {
 public:
  // The cached image whose first kSiiIdentityBytes equal `head`, or nullptr (also for serial 0).
  const SiiImage* find(ConstByteSpan head) const noexcept;
  // Takes in a complete image read from a slave (replacing the entry with the same first 32 bytes'
  // identity: vendor, product, revision, serial). False, and nothing kept, for an image that is
  // truncated, failed, shorter than the identity, has serial 0, does not parse with its CRC, or when
  // the cache is full.
  bool remember(const SiiImage& image) noexcept;

  std::size_t size() const noexcept { return count_; }
  bool changed() const noexcept { return changed_; }  // remember() took something in since decode/clear
  void clear() noexcept;

  // The file form; the encoded size, or capacity_exceeded when `out` is too small (kSiiCacheFileMax is enough).
  Result<std::size_t> encode(ByteSpan out) const noexcept;
  // Replaces the contents with the file's; on any error the cache is left empty and the error names the field.
  Status decode(ConstByteSpan in) noexcept;

 private:
  std::array<SiiImage, kSiiCacheCapacity> entries_{};
  std::size_t count_{0};
  bool changed_{false};
};

}  // namespace rescue::ecat
