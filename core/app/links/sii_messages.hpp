// ctl sii_read (docs/operator.md "SII", docs/protocol.md "SII images"): each slave's SII image as the
// master read it from the slave's EEPROM at bring-up. The EtherCAT handler publishes the images once
// after bring-up, one slave per period (TaskLinks::sii_images, SiiImageRecord); the socket handler
// answers get_sii from that copy, in chunks (SiiRequestPayload, SiiPayload): the cycle never waits for
// an operator's read and no frame carries it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace rescue::app::protocol {

constexpr std::size_t kSiiImageBytes = 1024;  // the master's image capacity (ecat::kSiiImageCapacity)
constexpr std::size_t kSiiChunkBytes = 512;   // one answer's bytes: two answers carry a whole image

constexpr std::uint8_t kSiiRead = 0x01;            // flags: the master read this slave's SII at bring-up
constexpr std::uint8_t kSiiFromCache = 0x02;       // the bytes after the identity came from the SII cache
constexpr std::uint8_t kSiiStringsSkipped = 0x04;  // bytes of the Strings category were not read: they read 0
constexpr std::uint8_t kSiiFlagsMask = 0x07;

// get_sii: the bytes of the image of the slave at position `slave` from `offset`.
struct SiiRequestPayload {
  std::uint8_t slave{0};
  std::uint16_t offset{0};
};

// sii: `length` bytes of the image from `offset` (bytes past `length` zero); `size`: the whole
// image's bytes (0 with flags 0: the master has no image of that slave).
struct SiiPayload {
  std::uint8_t slave{0};
  std::uint8_t flags{0};
  std::uint16_t size{0};
  std::uint16_t offset{0};
  std::uint16_t length{0};
  std::array<std::uint8_t, kSiiChunkBytes> bytes{};
};

}  // namespace rescue::app::protocol

namespace rescue::app {

// TaskLinks::sii_images[position]: one slave's image (trivial: a seqlock record). size 0: none.
struct SiiImageRecord {
  std::uint16_t size;
  std::uint8_t flags;  // protocol::kSii*
  std::array<std::uint8_t, 5> reserved;
  std::array<std::uint8_t, protocol::kSiiImageBytes> bytes;
};

}  // namespace rescue::app
