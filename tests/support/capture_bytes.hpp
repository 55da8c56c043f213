// Hand-built pcap and pcapng files for tests and fuzz seeds: any byte order, timestamp resolution,
// block kind, and deliberately odd contents. Independent of ecat/capture/capture_writer on purpose, so the
// reader is not only tested against our own writer. Tests only: allocates freely.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "ecat/capture/capture_format.hpp"

namespace rescue::test {

class ByteBuffer {
 public:
  explicit ByteBuffer(bool big_endian = false) : big_endian_(big_endian) {}
  void set_big_endian(bool big) { big_endian_ = big; }
  bool big_endian() const { return big_endian_; }
  void u8(std::uint8_t v) { bytes.push_back(v); }
  void u16(std::uint16_t v) {
    if (big_endian_) {
      u8(static_cast<std::uint8_t>(v >> 8));
      u8(static_cast<std::uint8_t>(v));
    } else {
      u8(static_cast<std::uint8_t>(v));
      u8(static_cast<std::uint8_t>(v >> 8));
    }
  }
  void u32(std::uint32_t v) {
    if (big_endian_) {
      u16(static_cast<std::uint16_t>(v >> 16));
      u16(static_cast<std::uint16_t>(v));
    } else {
      u16(static_cast<std::uint16_t>(v));
      u16(static_cast<std::uint16_t>(v >> 16));
    }
  }
  void u64(std::uint64_t v) {
    if (big_endian_) {
      u32(static_cast<std::uint32_t>(v >> 32));
      u32(static_cast<std::uint32_t>(v));
    } else {
      u32(static_cast<std::uint32_t>(v));
      u32(static_cast<std::uint32_t>(v >> 32));
    }
  }
  void raw(const std::vector<std::uint8_t>& data) { bytes.insert(bytes.end(), data.begin(), data.end()); }
  void pad4() {
    while (bytes.size() % 4 != 0) u8(0);
  }
  // Patches a u32 at `at` in the current byte order.
  void patch_u32(std::size_t at, std::uint32_t v) {
    ByteBuffer tmp(big_endian_);
    tmp.u32(v);
    for (std::size_t i = 0; i < 4; ++i) bytes[at + i] = tmp.bytes[i];
  }

  std::vector<std::uint8_t> bytes;

 private:
  bool big_endian_;
};

struct PcapngOption {
  std::uint16_t code;
  std::vector<std::uint8_t> value;
};

class PcapngBuilder {
 public:
  explicit PcapngBuilder(bool big_endian = false) { section(big_endian); }

  // A new section in its own byte order, which the blocks after it use; interface ids restart at 0.
  PcapngBuilder& section(bool big_endian) {
    buf_.set_big_endian(big_endian);
    const std::size_t at = begin(ecat::capture::kBlockSectionHeader);
    buf_.u32(ecat::capture::kByteOrderMagic);
    buf_.u16(1);
    buf_.u16(0);
    buf_.u64(~std::uint64_t{0});
    end(at);
    return *this;
  }

  PcapngBuilder& interface(std::uint16_t link_type = ecat::capture::kLinkTypeEthernet, std::uint32_t snap_length = 0,
                           std::optional<std::uint8_t> tsresol = std::nullopt,
                           std::optional<std::int64_t> tsoffset_s = std::nullopt,
                           std::optional<std::uint8_t> fcs_length = std::nullopt) {
    const std::size_t at = begin(ecat::capture::kBlockInterfaceDescription);
    buf_.u16(link_type);
    buf_.u16(0);
    buf_.u32(snap_length);
    if (tsresol) option(ecat::capture::kOptIfTimestampResolution, {*tsresol});
    if (tsoffset_s) {
      ByteBuffer v(big_endian());
      v.u64(static_cast<std::uint64_t>(*tsoffset_s));
      option(ecat::capture::kOptIfTimestampOffset, v.bytes);
    }
    if (fcs_length) option(ecat::capture::kOptIfFcsLength, {*fcs_length});
    if (tsresol || tsoffset_s || fcs_length) buf_.u32(0);
    end(at);
    return *this;
  }

  PcapngBuilder& packet(std::uint32_t interface_id, std::uint64_t ts_units, const std::vector<std::uint8_t>& data,
                        std::optional<std::uint32_t> flags = std::nullopt, std::optional<std::uint32_t> original = std::nullopt) {
    const std::size_t at = begin(ecat::capture::kBlockEnhancedPacket);
    buf_.u32(interface_id);
    buf_.u32(static_cast<std::uint32_t>(ts_units >> 32));
    buf_.u32(static_cast<std::uint32_t>(ts_units));
    buf_.u32(static_cast<std::uint32_t>(data.size()));
    buf_.u32(original.value_or(static_cast<std::uint32_t>(data.size())));
    buf_.raw(data);
    buf_.pad4();
    if (flags) {
      ByteBuffer v(big_endian());
      v.u32(*flags);
      option(ecat::capture::kOptEpbFlags, v.bytes);
      buf_.u32(0);
    }
    end(at);
    return *this;
  }

  PcapngBuilder& simple_packet(const std::vector<std::uint8_t>& data, std::optional<std::uint32_t> original = std::nullopt) {
    const std::size_t at = begin(ecat::capture::kBlockSimplePacket);
    buf_.u32(original.value_or(static_cast<std::uint32_t>(data.size())));
    buf_.raw(data);
    buf_.pad4();
    end(at);
    return *this;
  }

  PcapngBuilder& obsolete_packet(std::uint16_t interface_id, std::uint64_t ts_units, const std::vector<std::uint8_t>& data) {
    const std::size_t at = begin(ecat::capture::kBlockPacketObsolete);
    buf_.u16(interface_id);
    buf_.u16(0);  // drops
    buf_.u32(static_cast<std::uint32_t>(ts_units >> 32));
    buf_.u32(static_cast<std::uint32_t>(ts_units));
    buf_.u32(static_cast<std::uint32_t>(data.size()));
    buf_.u32(static_cast<std::uint32_t>(data.size()));
    buf_.raw(data);
    buf_.pad4();
    end(at);
    return *this;
  }

  // Any block with a raw body (name resolution, statistics, custom...), padded to 4.
  PcapngBuilder& block(std::uint32_t type, const std::vector<std::uint8_t>& body) {
    const std::size_t at = begin(type);
    buf_.raw(body);
    buf_.pad4();
    end(at);
    return *this;
  }

  const std::vector<std::uint8_t>& bytes() const { return buf_.bytes; }
  std::vector<std::uint8_t>& mutable_bytes() { return buf_.bytes; }
  bool big_endian() const { return buf_.big_endian(); }

 private:
  std::size_t begin(std::uint32_t type) {
    const std::size_t at = buf_.bytes.size();
    buf_.u32(type);
    buf_.u32(0);
    return at;
  }
  void end(std::size_t at) {
    const auto total = static_cast<std::uint32_t>(buf_.bytes.size() - at + 4);
    buf_.u32(total);
    buf_.patch_u32(at + 4, total);
  }
  void option(std::uint16_t code, const std::vector<std::uint8_t>& value) {
    buf_.u16(code);
    buf_.u16(static_cast<std::uint16_t>(value.size()));
    buf_.raw(value);
    buf_.pad4();
  }
  ByteBuffer buf_;
};

class PcapBuilder {
 public:
  PcapBuilder(bool big_endian, bool nanoseconds, std::uint32_t link_type = ecat::capture::kLinkTypeEthernet,
              std::uint32_t snap_length = 65535)
      : buf_(big_endian) {
    buf_.u32(nanoseconds ? ecat::capture::kPcapMagicNanoseconds : ecat::capture::kPcapMagicMicroseconds);
    buf_.u16(2);
    buf_.u16(4);
    buf_.u32(0);  // thiszone
    buf_.u32(0);  // sigfigs
    buf_.u32(snap_length);
    buf_.u32(link_type);
  }
  PcapBuilder& record(std::uint32_t seconds, std::uint32_t fraction, const std::vector<std::uint8_t>& data,
                      std::optional<std::uint32_t> original = std::nullopt) {
    buf_.u32(seconds);
    buf_.u32(fraction);
    buf_.u32(static_cast<std::uint32_t>(data.size()));
    buf_.u32(original.value_or(static_cast<std::uint32_t>(data.size())));
    buf_.raw(data);
    return *this;
  }
  const std::vector<std::uint8_t>& bytes() const { return buf_.bytes; }

 private:
  ByteBuffer buf_;
};

}  // namespace rescue::test
