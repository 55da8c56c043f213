#include "ecat/capture/capture_reader.hpp"

#include <array>
#include <limits>

#include "core/base/endian.hpp"

namespace rescue::ecat {
namespace {

using namespace capture;  // NOLINT(google-build-using-namespace): the format's names, in this file only

constexpr std::uint64_t kNsPerSecond = 1'000'000'000ULL;
constexpr std::uint64_t kMaxU64 = std::numeric_limits<std::uint64_t>::max();
constexpr std::size_t pad4(std::size_t n) noexcept { return (n + 3) & ~std::size_t{3}; }
constexpr std::uint32_t low32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

constexpr std::uint64_t power_of_ten(unsigned exponent) noexcept {
  std::uint64_t v = 1;
  for (unsigned i = 0; i < exponent; ++i) v *= 10;
  return v;
}

}  // namespace

Result<std::uint64_t> pcapng_timestamp_ns(std::uint64_t units, std::uint8_t tsresol, std::int64_t tsoffset_s) noexcept {
  const unsigned exponent = tsresol & 0x7FU;
  std::uint64_t ns = 0;
  if ((tsresol & kTsresolBinaryFlag) != 0) {
    if (exponent > 63) return make_error(Errc::unsupported, "if_tsresol", tsresol);
    const std::uint64_t seconds = units >> exponent;
    const std::uint64_t fraction = units & ((std::uint64_t{1} << exponent) - 1);
    // fraction * 1e9 fits 64 bits while fraction < 2^34; finer fractions lose bits below 1 ns.
    const std::uint64_t fraction_ns = exponent <= 34 ? (fraction * kNsPerSecond) >> exponent
                                                     : ((fraction >> (exponent - 34)) * kNsPerSecond) >> 34;
    if (seconds > (kMaxU64 - fraction_ns) / kNsPerSecond) return make_error(Errc::out_of_range, "timestamp");
    ns = seconds * kNsPerSecond + fraction_ns;
  } else if (exponent <= 9) {
    const std::uint64_t multiplier = power_of_ten(9 - exponent);
    if (units > kMaxU64 / multiplier) return make_error(Errc::out_of_range, "timestamp");
    ns = units * multiplier;
  } else if (exponent <= 28) {  // 10^19 is the largest power of ten in 64 bits
    ns = units / power_of_ten(exponent - 9);
  } else {
    return make_error(Errc::unsupported, "if_tsresol", tsresol);
  }
  if (tsoffset_s == 0) return ns;
  constexpr auto kMaxOffsetSeconds = static_cast<std::int64_t>(std::numeric_limits<std::int64_t>::max() / 1'000'000'000LL);
  if (tsoffset_s > kMaxOffsetSeconds || tsoffset_s < -kMaxOffsetSeconds) {
    return make_error(Errc::out_of_range, "timestamp");
  }
  if (tsoffset_s > 0) {
    const std::uint64_t add = static_cast<std::uint64_t>(tsoffset_s) * kNsPerSecond;
    if (ns > kMaxU64 - add) return make_error(Errc::out_of_range, "timestamp");
    return ns + add;
  }
  const std::uint64_t sub = static_cast<std::uint64_t>(-tsoffset_s) * kNsPerSecond;
  if (ns < sub) return make_error(Errc::out_of_range, "timestamp");
  return ns - sub;
}

Result<CaptureReader> CaptureReader::open(ConstByteSpan file) noexcept {
  CaptureReader r;
  r.file_ = file;
  return r.start();
}

Result<CaptureReader> CaptureReader::open(CaptureSource& source, ByteSpan window) noexcept {
  if (window.size() < kMinWindow) return make_error(Errc::invalid_argument, "capture window smaller than kMinWindow");
  CaptureReader r;
  r.source_ = &source;
  r.window_ = window;
  return r.start();
}

Result<std::size_t> CaptureReader::bytes_from(std::size_t at, std::size_t want) noexcept {
  const std::size_t end = base_ + file_.size();
  if (source_ == nullptr || (at >= base_ && at <= end && (want <= end - at || at_end_))) return end;
  // Streamed: the window refilled from `at` (a record or block starts there: nothing before it is
  // needed any more).
  const Result<std::size_t> got = source_->read_at(at, window_);
  if (!got.ok()) return error_at(Errc::io_error, "read", at);
  base_ = at;
  file_ = ConstByteSpan(window_.data(), got.value());
  at_end_ = got.value() < window_.size();  // the file ends inside the window
  return base_ + got.value();
}

Result<CaptureReader> CaptureReader::start() noexcept {
  CaptureReader& r = *this;
  const Result<std::size_t> head = bytes_from(0, kMinBlockSize + kShbFixedBody);
  if (!head.ok()) return head.error();
  const std::size_t size = head.value();
  if (size < 4) return r.error_at(Errc::truncated, "file header", 0);
  const std::uint32_t magic_le = load_le32(file_.data());
  const std::uint32_t magic_be = load_be32(file_.data());

  if (magic_le == kBlockSectionHeader) {
    r.format_ = CaptureFormat::pcapng;
    if (size < kMinBlockSize + kShbFixedBody) return r.error_at(Errc::truncated, "file header", 0);
    // The first section header goes through the same checks as any later one.
    CapturedFrame unused;
    const Result<bool> first = r.read_block(unused);
    if (!first.ok()) return first.error();
    return r;
  }

  const bool micro = magic_le == kPcapMagicMicroseconds || magic_be == kPcapMagicMicroseconds;
  const bool nano = magic_le == kPcapMagicNanoseconds || magic_be == kPcapMagicNanoseconds;
  if (!micro && !nano) return r.error_at(Errc::unsupported, "file format", 0);
  r.format_ = CaptureFormat::pcap;
  r.big_endian_ = magic_be == kPcapMagicMicroseconds || magic_be == kPcapMagicNanoseconds;
  r.nanoseconds_ = nano;
  if (size < kPcapFileHeaderSize) return r.error_at(Errc::truncated, "file header", 0);
  if (r.u16(4) != kPcapMajor) return r.error_at(Errc::version, "pcap version", 4);
  const std::uint32_t link = r.u32(20);
  r.pcap_interface_.link_type = static_cast<std::uint16_t>(link & 0xFFFFU);
  r.pcap_interface_.snap_length = r.u32(16);
  if ((link & kPcapFcsPresentFlag) != 0) {
    r.pcap_interface_.fcs_length = static_cast<std::uint8_t>(((link >> kPcapFcsLengthShift) & 0xFU) * 2U);
  }
  r.offset_ = kPcapFileHeaderSize;
  return r;
}

Result<bool> CaptureReader::next(CapturedFrame& out) noexcept {
  if (failed_.code != Errc::ok) return failed_;
  return format_ == CaptureFormat::pcap ? next_pcap(out) : next_pcapng(out);
}

Result<bool> CaptureReader::next_pcap(CapturedFrame& out) noexcept {
  const std::size_t at = offset_;
  const Result<std::size_t> head = bytes_from(at, kPcapRecordHeaderSize + kMaxPacketLength);
  if (!head.ok()) return fail(head.error());
  const std::size_t size = head.value();
  if (at == size) return false;
  if (size - at < kPcapRecordHeaderSize) return fail(error_at(Errc::truncated, "pcap record header", at));
  const std::uint32_t seconds = u32(at);
  const std::uint32_t fraction = u32(at + 4);
  const std::uint32_t captured = u32(at + 8);
  if (captured > kMaxPacketLength) return fail(error_at(Errc::malformed, "pcap record length", at + 8));
  if (captured > size - at - kPcapRecordHeaderSize) {
    return fail(error_at(Errc::truncated, "pcap record data", at + 8));
  }
  CapturedFrame frame;
  frame.number = frames_read_ + 1;
  frame.bytes = file_.subspan(at + kPcapRecordHeaderSize - base_, captured);
  frame.original_length = u32(at + 12);
  // At most (2^32 - 1) s * 1e9 + (2^32 - 1) * 1000: fits 64 bits.
  frame.timestamp_ns = static_cast<std::uint64_t>(seconds) * kNsPerSecond + static_cast<std::uint64_t>(fraction) * (nanoseconds_ ? 1U : 1000U);
  frame.link_type = pcap_interface_.link_type;
  frame.fcs_length = pcap_interface_.fcs_length;
  out = frame;
  offset_ = at + kPcapRecordHeaderSize + captured;
  ++frames_read_;
  return true;
}

Result<bool> CaptureReader::next_pcapng(CapturedFrame& out) noexcept {
  for (;;) {
    const Result<std::size_t> end = bytes_from(offset_, kMinBlockSize);
    if (!end.ok()) return fail(end.error());
    if (end.value() == offset_) return false;
    const Result<bool> packet = read_block(out);
    if (!packet.ok()) return packet.error();
    if (packet.value()) return true;
  }
}

Result<bool> CaptureReader::read_block(CapturedFrame& out) noexcept {
  const std::size_t at = offset_;
  const Result<std::size_t> head = bytes_from(at, kMinBlockSize);
  if (!head.ok()) return fail(head.error());
  std::size_t size = head.value();
  if (size - at < kMinBlockSize) return fail(error_at(Errc::truncated, "block header", at));
  const std::uint8_t* const block = file_.data() + (at - base_);
  if (load_le32(block) == kBlockSectionHeader) {  // reads the same in both byte orders
    // A new section: its byte order comes from the magic right after the length.
    if (load_le32(block + kBlockHeaderSize) == kByteOrderMagic) {
      big_endian_ = false;
    } else if (load_be32(block + kBlockHeaderSize) == kByteOrderMagic) {
      big_endian_ = true;
    } else {
      return fail(error_at(Errc::malformed, "byte-order magic", at + kBlockHeaderSize));
    }
  }
  const std::uint32_t type = u32(at);
  const std::uint32_t length = u32(at + 4);
  if (length < kMinBlockSize || length % 4 != 0) return fail(error_at(Errc::malformed, "block length", at + 4));
  if (source_ != nullptr && length > window_.size()) {
    // Too large for the window: refused for its size only when the file really holds it (a
    // length running past the end of the file is the truncation the whole-file reader reports).
    RESCUE_TRY(block_fits_in_file(at, length));
    return fail(error_at(Errc::capacity_exceeded, "block length", at + 4));
  }
  const Result<std::size_t> whole = bytes_from(at, length);
  if (!whole.ok()) return fail(whole.error());
  size = whole.value();
  if (length > size - at) return fail(error_at(Errc::truncated, "block length", at + 4));
  if (u32(at + length - kBlockTrailerSize) != length) {
    return fail(error_at(Errc::malformed, "block trailer", at + length - kBlockTrailerSize));
  }
  bool packet = false;
  if (type == kBlockSectionHeader) {
    RESCUE_TRY(read_section_header(at, length));
  } else if (type == kBlockInterfaceDescription) {
    RESCUE_TRY(read_interface(at, length));
  } else if (type == kBlockEnhancedPacket || type == kBlockSimplePacket || type == kBlockPacketObsolete) {
    RESCUE_TRY(read_packet(type, at, length, out));
    packet = true;
  }  // any other block (name resolution, statistics, ...) is skipped
  offset_ = at + length;
  if (packet) ++frames_read_;
  return packet;
}

Status CaptureReader::block_fits_in_file(std::size_t at, std::size_t length) noexcept {
  std::array<std::uint8_t, kBlockTrailerSize> trailer{};
  const Result<std::size_t> got = source_->read_at(at + length - kBlockTrailerSize, ByteSpan(trailer.data(), trailer.size()));
  if (!got.ok()) return fail(error_at(Errc::io_error, "read", at + length - kBlockTrailerSize));
  if (got.value() < trailer.size()) return fail(error_at(Errc::truncated, "block length", at + 4));
  return Status::success();
}

Status CaptureReader::read_section_header(std::size_t at, std::size_t length) noexcept {
  if (length < kMinBlockSize + kShbFixedBody) return fail(error_at(Errc::malformed, "block body", at + 4));
  if (u16(at + 12) != kPcapngMajor) return fail(error_at(Errc::version, "pcapng version", at + 12));
  interfaces_.clear();  // interface ids restart in every section
  return Status::success();
}

Status CaptureReader::read_interface(std::size_t at, std::size_t length) noexcept {
  if (length < kMinBlockSize + kIdbFixedBody) return fail(error_at(Errc::malformed, "block body", at + 4));
  Interface itf;
  itf.link_type = u16(at + 8);
  itf.snap_length = u32(at + 12);
  const std::size_t end = at + length - kBlockTrailerSize;
  std::size_t p = at + kBlockHeaderSize + kIdbFixedBody;
  while (end - p >= 4) {
    const std::uint16_t code = u16(p);
    const std::uint16_t n = u16(p + 2);
    if (code == kOptEndOfOptions) break;
    if (n > end - p - 4) return fail(error_at(Errc::malformed, "option length", p + 2));
    const std::size_t value = p + 4;
    if (code == kOptIfTimestampResolution) {
      if (n < 1) return fail(error_at(Errc::malformed, "option length", p + 2));
      itf.tsresol = byte(value);
      const auto probe = pcapng_timestamp_ns(0, itf.tsresol, 0);
      if (!probe.ok()) return fail(error_at(Errc::unsupported, "if_tsresol", value));
    } else if (code == kOptIfTimestampOffset) {
      if (n < 8) return fail(error_at(Errc::malformed, "option length", p + 2));
      const std::uint64_t raw = big_endian_ ? load_be64(file_.data() + (value - base_)) : load_le64(file_.data() + (value - base_));
      itf.tsoffset_s = static_cast<std::int64_t>(raw);
    } else if (code == kOptIfFcsLength) {
      if (n < 1) return fail(error_at(Errc::malformed, "option length", p + 2));
      itf.fcs_length = byte(value);
    }
    const std::size_t step = 4 + pad4(n);
    if (step > end - p) break;  // padding of the last option cut short: nothing more to read
    p += step;
  }
  if (!interfaces_.push_back(itf)) return fail(error_at(Errc::capacity_exceeded, "interfaces", at));
  return Status::success();
}

Status CaptureReader::read_packet(std::uint32_t type, std::size_t at, std::size_t length,
                                        CapturedFrame& out) noexcept {
  const std::size_t body = length - kMinBlockSize;
  const std::size_t end = at + length - kBlockTrailerSize;
  CapturedFrame frame;
  frame.number = frames_read_ + 1;
  std::uint32_t interface_id = 0;
  std::size_t data_at = 0;
  std::size_t captured = 0;
  std::uint64_t units = 0;

  if (type == kBlockSimplePacket) {
    if (body < kSpbFixedBody) return fail(error_at(Errc::malformed, "block body", at + 4));
    if (interfaces_.empty()) return fail(error_at(Errc::out_of_range, "interface id", at));
    frame.original_length = u32(at + 8);
    data_at = at + kBlockHeaderSize + kSpbFixedBody;
    captured = frame.original_length;
    if (captured > body - kSpbFixedBody) captured = body - kSpbFixedBody;
    if (interfaces_[0].snap_length != 0 && captured > interfaces_[0].snap_length) captured = interfaces_[0].snap_length;
  } else {
    // Enhanced and obsolete packet blocks share the layout but for a 16-bit interface id (+ drops).
    if (body < kEpbFixedBody) return fail(error_at(Errc::malformed, "block body", at + 4));
    interface_id = type == kBlockEnhancedPacket ? u32(at + 8) : u16(at + 8);
    units = (std::uint64_t{u32(at + 12)} << 32) | u32(at + 16);
    captured = u32(at + 20);
    frame.original_length = u32(at + 24);
    data_at = at + kBlockHeaderSize + kEpbFixedBody;
    if (captured > body - kEpbFixedBody || pad4(captured) > body - kEpbFixedBody) {
      return fail(error_at(Errc::malformed, "captured length", at + 20));
    }
    if (interface_id >= interfaces_.size()) return fail(error_at(Errc::out_of_range, "interface id", at + 8));
    std::size_t p = data_at + pad4(captured);
    while (end - p >= 4) {
      const std::uint16_t code = u16(p);
      const std::uint16_t n = u16(p + 2);
      if (code == kOptEndOfOptions) break;
      if (n > end - p - 4) return fail(error_at(Errc::malformed, "option length", p + 2));
      if (code == kOptEpbFlags && n >= 4) {
        const std::uint32_t direction = u32(p + 4) & kEpbFlagsDirectionMask;
        frame.direction = direction <= 2 ? static_cast<FrameDirection>(direction) : FrameDirection::unknown;
      }
      const std::size_t step = 4 + pad4(n);
      if (step > end - p) break;
      p += step;
    }
  }

  const Interface& itf = interfaces_[interface_id];
  if (type != kBlockSimplePacket) {
    const auto ns = pcapng_timestamp_ns(units, itf.tsresol, itf.tsoffset_s);
    if (!ns.ok()) return fail(error_at(ns.error().code, ns.error().what, at + 12));
    frame.timestamp_ns = ns.value();
  }
  frame.bytes = file_.subspan(data_at - base_, captured);
  frame.link_type = itf.link_type;
  frame.interface_id = interface_id;
  frame.fcs_length = itf.fcs_length;
  out = frame;
  return Status::success();
}

Error CaptureReader::fail(Error error) noexcept {
  failed_ = error;
  return error;
}

std::uint16_t CaptureReader::u16(std::size_t at) const noexcept {
  return big_endian_ ? load_be16(file_.data() + (at - base_)) : load_le16(file_.data() + (at - base_));
}

std::uint32_t CaptureReader::u32(std::size_t at) const noexcept {
  return big_endian_ ? load_be32(file_.data() + (at - base_)) : load_le32(file_.data() + (at - base_));
}

Error CaptureReader::error_at(Errc code, const char* what, std::size_t at) const noexcept {
  return make_error(code, what, frames_read_ + 1, low32(at));
}

}  // namespace rescue::ecat
