// CaptureReader: walks the packets of a pcapng or classic pcap file, held in memory by the caller or
// read through a CaptureSource into a window of the caller's (bounded memory whatever the file's
// size: one record or block at a time; a pcapng block larger than the window is refused, never
// read in part). The bytes are untrusted: every block length, option length and packet length
// is checked against the bytes that are there before anything is read, and a problem gives an
// error value naming the field, never a read out of bounds. Frames are views into the caller's
// buffer (zero copy).
//
// Reads: pcapng in either byte order, several sections, up to kMaxInterfaces interfaces per
// section, enhanced / simple / obsolete packet blocks, if_tsresol (decimal and binary),
// if_tsoffset, if_fcslen and epb_flags; other blocks are skipped. Classic pcap in either byte
// order, microsecond and nanosecond magic, and the FCS-length bits of the link-type field.
//
// A section header's section length is advisory and not read: the pcapng spec lets it be -1
// (unknown) and uses it only to skip a section; blocks are walked one by one, each checked by its
// own length, so a section length of any value (0xffffffffffffffc9, or one disagreeing with the
// blocks that follow) changes nothing the reader returns.
//
// Error values (Error::what, code; detail0 = number of the frame being read, 1-based, i.e. frames
// read so far + 1; detail1 = byte offset in the file of the field that failed, low 32 bits):
//   "file header"            truncated    fewer bytes than the format's file header
//   "file format"            unsupported  neither pcap nor pcapng magic
//   "pcap version"           version      classic pcap major version other than 2
//   "pcap record header"     truncated    fewer than 16 bytes for a record header
//   "pcap record length"     malformed    captured length above 256 KiB
//   "pcap record data"       truncated    captured length beyond the end of the file
//   "block header"           truncated    fewer than 12 bytes where a block starts
//   "block length"           malformed    below 12 or not a multiple of 4
//   "block length"           truncated    block runs past the end of the file
//   "block trailer"          malformed    trailing length differs from the leading one
//   "byte-order magic"       malformed    section header's magic is neither byte order
//   "pcapng version"         version      section major version other than 1
//   "block body"             malformed    body shorter than the block type's fixed fields
//   "captured length"        malformed    packet data runs past the block body
//   "interface id"           out_of_range packet names an interface the section did not describe
//   "interfaces"             capacity_exceeded  more than kMaxInterfaces in one section
//   "option length"          malformed    an option runs past the block body
//   "if_tsresol"             unsupported  a resolution finer than 64-bit nanoseconds can hold
//   "timestamp"              out_of_range the timestamp in ns does not fit 64 bits (or is < 0)
//   "block length"           capacity_exceeded  (streamed) a block larger than the reader's window that
//                                               the file holds whole (else truncated, as above)
//   "read"                   io_error     (streamed) the source could not be read
// After an error, next() returns the same error again.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/containers/fixed_vector.hpp"
#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/capture/capture_format.hpp"

namespace rescue::ecat {

enum class CaptureFormat : std::uint8_t { pcap, pcapng };

struct CapturedFrame {
  std::uint32_t number{0};          // 1-based over all packet records (Wireshark's frame.number)
  ConstByteSpan bytes{};            // captured bytes; may be shorter than original_length
  std::uint32_t original_length{0};
  std::uint64_t timestamp_ns{0};    // since the Unix epoch (0 for simple packet blocks)
  std::uint16_t link_type{0};       // capture::kLinkTypeEthernet for Ethernet
  std::uint32_t interface_id{0};
  std::uint8_t fcs_length{0};       // bytes of FCS at the end of `bytes`, when the file says so
  FrameDirection direction{FrameDirection::unknown};
};

// Where a streamed capture's bytes come from: up to out.size() bytes at `offset` into `out`, the
// count read (fewer only at the end of the file).
class CaptureSource {
 public:
  CaptureSource() = default;
  CaptureSource(const CaptureSource&) = delete;
  CaptureSource& operator=(const CaptureSource&) = delete;
  CaptureSource(CaptureSource&&) = delete;
  CaptureSource& operator=(CaptureSource&&) = delete;
  virtual ~CaptureSource() = default;
  virtual Result<std::size_t> read_at(std::size_t offset, ByteSpan out) noexcept = 0;
};

class CaptureReader {
 public:
  static constexpr std::size_t kMaxInterfaces = 16;
  // A streamed reader's window holds the largest record (kMaxPacketLength and its header) and more.
  static constexpr std::size_t kMinWindow = std::size_t{2} * capture::kMaxPacketLength;

  // Recognises the format and checks the file header (and for pcapng the first section header).
  static Result<CaptureReader> open(ConstByteSpan file) noexcept;
  // The same over `source`, read record by record into `window` (at least kMinWindow bytes; the
  // frames returned by next() are views into it, valid until the next call).
  static Result<CaptureReader> open(CaptureSource& source, ByteSpan window) noexcept;

  // The next packet into `out`: true, or false at the end of the file.
  Result<bool> next(CapturedFrame& out) noexcept;

  CaptureFormat format() const noexcept { return format_; }
  std::uint32_t frames_read() const noexcept { return frames_read_; }
  std::size_t offset() const noexcept { return offset_; }  // where the next block or record starts

 private:
  struct Interface {
    std::uint16_t link_type{0};
    std::uint32_t snap_length{0};
    std::uint8_t tsresol{capture::kTsresolMicroseconds};
    std::int64_t tsoffset_s{0};
    std::uint8_t fcs_length{0};
  };

  Result<CaptureReader> start() noexcept;
  // The absolute end of the bytes at hand from `at`, reading up to `want` of them into the window
  // when streamed (fewer only at the end of the file).
  Result<std::size_t> bytes_from(std::size_t at, std::size_t want) noexcept;
  std::uint8_t byte(std::size_t at) const noexcept { return file_[at - base_]; }
  Result<bool> next_pcap(CapturedFrame& out) noexcept;
  Result<bool> next_pcapng(CapturedFrame& out) noexcept;
  Status read_section_header(std::size_t at, std::size_t length) noexcept;
  Status read_interface(std::size_t at, std::size_t length) noexcept;
  Result<bool> read_block(CapturedFrame& out) noexcept;  // one pcapng block; true when it was a packet
  // Streamed, a block longer than the window: truncated "block length" when the file ends before it.
  Status block_fits_in_file(std::size_t at, std::size_t length) noexcept;
  Status read_packet(std::uint32_t type, std::size_t at, std::size_t length, CapturedFrame& out) noexcept;
  Error fail(Error error) noexcept;  // remembers the error: next() repeats it

  std::uint16_t u16(std::size_t at) const noexcept;
  std::uint32_t u32(std::size_t at) const noexcept;
  Error error_at(Errc code, const char* what, std::size_t at) const noexcept;

  ConstByteSpan file_{};     // the bytes at hand: the whole file, or the window's filled part
  std::size_t base_{0};      // offset in the file of file_[0]
  CaptureSource* source_{nullptr};
  ByteSpan window_{};
  bool at_end_{false};       // streamed: the window holds the end of the file
  CaptureFormat format_{CaptureFormat::pcapng};
  bool big_endian_{false};
  bool nanoseconds_{false};  // classic pcap: fraction in ns (else us)
  std::size_t offset_{0};
  std::uint32_t frames_read_{0};
  Interface pcap_interface_{};  // classic pcap: the one interface the file header describes
  FixedVector<Interface, kMaxInterfaces> interfaces_{};
  Error failed_{};  // sticky error: code ok while none
};

// Nanoseconds since the epoch of a pcapng timestamp in units of if_tsresol plus if_tsoffset
// seconds (exposed for tests). unsupported "if_tsresol" / out_of_range "timestamp".
Result<std::uint64_t> pcapng_timestamp_ns(std::uint64_t units, std::uint8_t tsresol, std::int64_t tsoffset_s) noexcept;

}  // namespace rescue::ecat
