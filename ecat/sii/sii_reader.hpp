// Reading the SII (EEPROM) of every slave through its ESC's EEPROM interface (0x0500-0x050F), all
// slaves in parallel: each frame carries one datagram per slave, addressed by auto-increment
// position, so the whole network's SII costs what one slave's costs.
//
// One read of a word address, per slave:
//   APWR 0x0502 (6 bytes): command = read (0x0100), word address (u32)
//   APRD 0x0502 (14 bytes): control/status, address, data; repeated while the busy bit (0x8000)
//        is set, up to the busy timeout; the data (0x0508) then holds 8 bytes (status bit 6) or 4.
//   A command error (0x2000) is acknowledged by the next command and the read is repeated.
// The reader starts with the header, then walks the categories as their headers arrive and stops
// at the end marker (0xFFFF). It reads what the master uses, as SOEM does, not every byte:
//   - the header's reserved words 0x1D..0x3D are not read (they stay zero in the image);
//   - the Strings category's body is put off, and after the end marker read only as far as the
//     strings the General category names (group, order, device name): the PDO and sync names that
//     fill most of it are not read (`strings_skipped` bytes, zero in the image; they parse as empty
//     strings). A drive's 624-byte image takes 84 EEPROM reads instead of 157; `all_strings`
//     reads every string.
// With a cache (sii_cache.hpp), once a slave's first 32 bytes (configuration area and identity:
// vendor, product, revision, serial) are read, an image cached for exactly those bytes is taken
// instead of reading on: 8 EEPROM reads instead of 84. A category that would not fit the image
// buffer ends the image there (an end marker is put in its place, `truncated` says so).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/link/datagram_link.hpp"

namespace rescue::ecat {

constexpr std::size_t kSiiImageCapacity = 1024;
constexpr std::size_t kSiiHeaderBytes = 128;
constexpr std::size_t kSiiIdentityBytes = 32;  // words 0..15: configuration area (CRC in word 7), vendor, product, revision, serial

struct SiiImage {
  std::array<std::uint8_t, kSiiImageCapacity> bytes{};
  std::uint16_t size{0};       // bytes of `bytes` that hold the image (end marker included)
  bool complete{false};        // the end marker was read (or put in, when truncated)
  bool truncated{false};
  bool from_cache{false};      // the identity was read, the rest taken from the SII cache
  std::uint16_t strings_skipped{0};  // bytes of the Strings category not read (zero in `bytes`); not kept in the cache file
  Error error{};               // why the read failed (code ok when it did not)
  ConstByteSpan view() const noexcept { return {bytes.data(), size}; }
};

struct SiiReadOptions {
  hal::Nanoseconds frame_timeout{2 * hal::kNsPerMs};   // one frame's round trip
  hal::Nanoseconds busy_timeout{20 * hal::kNsPerMs};   // one EEPROM read
  unsigned command_retries{3};
  unsigned attempts{3};  // sends of a frame that does not come back (reads and commands repeat safely)
  bool all_strings{false};  // read every string, not only those the General category names
};

struct SiiReadStats {
  std::uint32_t frames{0};
  std::uint32_t reads{0};  // EEPROM reads that returned data, all slaves together
  std::uint32_t busy_polls{0};
  std::uint32_t command_errors{0};
  std::uint32_t cache_hits{0};  // slaves whose image came from the cache after their first 32 bytes
};

class SiiCache;

// Reads the SII images of the slaves at auto-increment positions 0 .. images.size()-1. Fails only
// when the network stops answering; a slave whose read failed has its `error` set. `cache` may be
// null (every image read whole).
Result<SiiReadStats> read_sii_images(DatagramLink& link, Span<SiiImage> images, const SiiReadOptions& options,
                                     const SiiCache* cache = nullptr) noexcept;

}  // namespace rescue::ecat
