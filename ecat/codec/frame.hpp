// EtherCAT frame codec (ETG.1000.4 section 5): Ethernet II with EtherType 0x88A4 (optionally one
// 802.1Q tag), the 2-byte EtherCAT header and a sequence of datagrams.
//
//   Ethernet   dst[6] src[6] (0x8100 tci)? type=0x88A4 (big-endian)
//   EtherCAT   u16 LE: length[10:0] reserved[11] type[15:12] (type 1 = datagrams)
//   datagram   cmd u8 | idx u8 | address u32 (ADP u16, ADO u16 or logical u32) |
//              u16: len[10:0] reserved[13:11] circulating[14] more_follows[15] | irq u16 |
//              data[len] | wkc u16
//
// FrameView::parse walks the whole frame once and checks every length and offset against the
// buffer; after that, iterating datagrams needs no checks. Views point into the caller's buffer
// (zero copy); MutableFrameView lets the simulator write data and working counters in place.
// FrameBuilder fills a fixed 1514-byte buffer and refuses a datagram that does not fit.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "core/base/endian.hpp"
#include "ecat/codec/command.hpp"

namespace rescue::ecat {

constexpr std::uint16_t kEtherTypeEtherCAT = 0x88A4;
constexpr std::uint16_t kEtherTypeVlan = 0x8100;
constexpr std::size_t kEthernetHeaderSize = 14;
constexpr std::size_t kVlanTagSize = 4;
constexpr std::size_t kMaxFrameSize = 1514;   // without FCS
constexpr std::size_t kMinFrameSize = 60;     // without FCS; shorter frames are padded
constexpr std::size_t kEcatHeaderSize = 2;
constexpr std::size_t kDatagramHeaderSize = 10;
constexpr std::size_t kWkcSize = 2;
constexpr std::size_t kDatagramOverhead = kDatagramHeaderSize + kWkcSize;
constexpr std::size_t kMaxEcatPayload = kMaxFrameSize - kEthernetHeaderSize - kEcatHeaderSize;  // 1498
constexpr std::size_t kMaxDatagramDataLength = kMaxEcatPayload - kDatagramOverhead;            // 1486
constexpr std::uint8_t kEcatTypeDatagrams = 1;
// More than this many datagrams cannot fit one frame (each takes at least 12 bytes).
constexpr std::size_t kMaxDatagramsPerFrame = kMaxEcatPayload / kDatagramOverhead;  // 124

using MacAddress = std::array<std::uint8_t, 6>;
constexpr MacAddress kBroadcastMac{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};

// A datagram inside a parsed frame. B is `const std::uint8_t` (read-only) or `std::uint8_t`.
template <typename B>
class BasicDatagramView {
 public:
  BasicDatagramView() = default;
  BasicDatagramView(B* header, std::uint32_t index_in_frame) noexcept : p_(header), index_in_frame_(index_in_frame) {}

  Command command() const noexcept { return static_cast<Command>(p_[0]); }
  std::uint8_t index() const noexcept { return p_[1]; }
  std::uint32_t address() const noexcept { return load_le32(p_ + 2); }
  std::uint16_t adp() const noexcept { return address_adp(address()); }
  std::uint16_t ado() const noexcept { return address_ado(address()); }
  std::uint16_t length() const noexcept { return static_cast<std::uint16_t>(load_le16(p_ + 6) & kLengthMask); }
  bool circulating() const noexcept { return (load_le16(p_ + 6) & kCirculatingBit) != 0; }
  bool more_follows() const noexcept { return (load_le16(p_ + 6) & kMoreFollowsBit) != 0; }
  std::uint16_t irq() const noexcept { return load_le16(p_ + 8); }
  Span<B> data() const noexcept { return Span<B>(p_ + kDatagramHeaderSize, length()); }
  std::uint16_t wkc() const noexcept { return load_le16(p_ + kDatagramHeaderSize + length()); }
  std::uint32_t index_in_frame() const noexcept { return index_in_frame_; }
  // Whole datagram: header, data and working counter.
  std::size_t wire_size() const noexcept { return kDatagramOverhead + length(); }
  B* raw() const noexcept { return p_; }

  // Mutators (only for mutable views): what a slave does to a passing datagram.
  template <typename X = B, typename = std::enable_if_t<!std::is_const<X>::value>>
  void set_wkc(std::uint16_t wkc) const noexcept {
    store_le16(p_ + kDatagramHeaderSize + length(), wkc);
  }
  // Slaves increment ADP of auto-increment and broadcast datagrams as they pass.
  template <typename X = B, typename = std::enable_if_t<!std::is_const<X>::value>>
  void set_adp(std::uint16_t adp) const noexcept {
    store_le16(p_ + 2, adp);
  }
  template <typename X = B, typename = std::enable_if_t<!std::is_const<X>::value>>
  void set_circulating(bool on) const noexcept {
    const std::uint16_t v = load_le16(p_ + 6);
    store_le16(p_ + 6, static_cast<std::uint16_t>(on ? (v | kCirculatingBit) : (v & ~kCirculatingBit)));
  }

  static constexpr std::uint16_t kLengthMask = 0x07FF;
  static constexpr std::uint16_t kCirculatingBit = 0x4000;
  static constexpr std::uint16_t kMoreFollowsBit = 0x8000;

 private:
  B* p_{nullptr};
  std::uint32_t index_in_frame_{0};
};

using DatagramView = BasicDatagramView<const std::uint8_t>;
using MutableDatagramView = BasicDatagramView<std::uint8_t>;

struct FrameHeader {
  MacAddress destination{};
  MacAddress source{};
  bool vlan_tagged{false};
  std::uint16_t vlan_tci{0};
  std::uint16_t ecat_length{0};  // bytes of datagrams announced by the EtherCAT header
  std::uint8_t ecat_type{0};
  std::size_t ecat_offset{0};    // offset of the EtherCAT header in the frame
  std::size_t datagram_count{0};
  // Zero bytes after the last datagram inside ecat_length: a master that pads an odd-length
  // datagram to an even length announces them (Wireshark shows them as "Pad bytes").
  std::uint16_t padding{0};

  // One past the last EtherCAT byte (datagrams and their padding); what follows (Ethernet padding,
  // a captured FCS) is not EtherCAT.
  std::size_t ecat_end() const noexcept { return ecat_offset + kEcatHeaderSize + ecat_length; }
};

// Error values of parse(): Error::what names the field, detail0 the datagram index (0-based, or
// kFrameLevel for frame-level fields), detail1 the byte offset in the frame of the field that failed.
//
//   code         what                         detail0          detail1
//   truncated    "ethernet header"            kFrameLevel      0 (frame shorter than 14 bytes)
//   malformed    "frame too long"             kFrameLevel      frame size (> 1522: 1514 + VLAN + FCS)
//   truncated    "vlan tag"                   kFrameLevel      12 (offset of the 0x8100 tag)
//   unsupported  "not EtherCAT"               kFrameLevel      offset of the EtherType (12 or 16)
//   truncated    "ecat header"                kFrameLevel      offset of the EtherCAT header
//   unsupported  "ecat type"                  kFrameLevel      offset of the EtherCAT header
//   truncated    "ecat length"                kFrameLevel      offset of the EtherCAT header
//   malformed    "datagram count"             124              offset where datagram 125 would start
//   truncated    "datagram header"            datagram index   offset of that datagram's header
//   malformed    "datagram command"           datagram index   offset of that datagram's header
//   truncated    "datagram length"            datagram index   offset of its length field (header + 6)
//   malformed    "bytes after last datagram"  datagrams parsed offset of the first unused byte
//
// Bytes after the last datagram inside the EtherCAT length are padding (FrameHeader::padding) when
// they are fewer than a datagram's 12-byte overhead and all zero: real masters pad an odd-length
// datagram to an even length that way. Anything else there (a non-zero byte, or room for a whole
// datagram whose more-follows bit is missing) is garbage: "bytes after last datagram".
//
// "truncated" means the frame (or the EtherCAT length) ends before a field it announces. Frames of
// other EtherTypes give unsupported "not EtherCAT": callers skip them. Bytes after ecat_end()
// (Ethernet padding, an FCS a capture kept) are ignored.
constexpr std::uint32_t kFrameLevel = 0xFFFFFFFFU;

template <typename B>
class BasicFrameView {
 public:
  static Result<BasicFrameView> parse(Span<B> frame) noexcept;
  // The same checks from the EtherCAT header on, for frames whose link layer is not Ethernet II
  // (Linux cooked captures): `ecat_offset` is where the EtherCAT header starts in `frame`, which
  // must be <= frame.size(). destination/source stay zero. Error offsets are offsets in `frame`.
  static Result<BasicFrameView> parse_ecat(Span<B> frame, std::size_t ecat_offset) noexcept;

  const FrameHeader& header() const noexcept { return header_; }
  std::size_t datagram_count() const noexcept { return header_.datagram_count; }
  Span<B> bytes() const noexcept { return frame_; }

  class Iterator {
   public:
    Iterator(B* p, std::uint32_t i, std::uint32_t n) noexcept : p_(p), i_(i), n_(n) {}
    BasicDatagramView<B> operator*() const noexcept { return BasicDatagramView<B>(p_, i_); }
    Iterator& operator++() noexcept {
      p_ += BasicDatagramView<B>(p_, i_).wire_size();
      ++i_;
      return *this;
    }
    bool operator!=(const Iterator& o) const noexcept { return i_ != o.i_; }

   private:
    B* p_;
    std::uint32_t i_;
    std::uint32_t n_;
  };
  Iterator begin() const noexcept {
    return Iterator(frame_.data() + header_.ecat_offset + kEcatHeaderSize, 0,
                    static_cast<std::uint32_t>(header_.datagram_count));
  }
  Iterator end() const noexcept {
    return Iterator(nullptr, static_cast<std::uint32_t>(header_.datagram_count),
                    static_cast<std::uint32_t>(header_.datagram_count));
  }

 private:
  Span<B> frame_{};
  FrameHeader header_{};
};

using FrameView = BasicFrameView<const std::uint8_t>;
using MutableFrameView = BasicFrameView<std::uint8_t>;

// Where a datagram added to a FrameBuilder sits, so its data can be filled or read later.
struct DatagramSlot {
  std::size_t header_offset{0};  // offset of the datagram header in the frame
  std::size_t data_offset{0};    // offset of its data in the frame
  std::uint16_t length{0};
};

class FrameBuilder {
 public:
  FrameBuilder() noexcept { reset(MacAddress{}); }

  // Starts a new frame from `source` to `destination` (broadcast by default, as masters do).
  void reset(const MacAddress& source, const MacAddress& destination = kBroadcastMac) noexcept;

  // Appends a datagram. `data` may be empty (the data field is zero-filled) or exactly `length`
  // bytes. Fails with capacity_exceeded ("frame full") and leaves the frame unchanged when it does
  // not fit, invalid_argument for bad lengths.
  Result<DatagramSlot> add(Command command, std::uint8_t index, std::uint32_t address, std::uint16_t length,
                           ConstByteSpan data = {}, std::uint16_t irq = 0, std::uint16_t wkc = 0) noexcept;

  // Bytes still free for datagram data after the 12 bytes of one more datagram's overhead.
  std::size_t remaining_data_capacity() const noexcept;
  std::size_t datagram_count() const noexcept { return count_; }

  // Mutable access to a datagram's data after add(), before or after finish().
  ByteSpan data(const DatagramSlot& slot) noexcept { return {buffer_.data() + slot.data_offset, slot.length}; }

  // Completes the frame: EtherCAT length, more-follows bits, padding to 60 bytes. The returned
  // view stays valid until the next reset()/add().
  ConstByteSpan finish() noexcept;

 private:
  std::array<std::uint8_t, kMaxFrameSize> buffer_{};
  std::size_t size_{0};  // bytes used so far (headers + datagrams)
  std::size_t count_{0};
  std::size_t last_header_offset_{0};
};

// Explicit instantiation lives in frame.cpp.
extern template class BasicFrameView<const std::uint8_t>;
extern template class BasicFrameView<std::uint8_t>;

}  // namespace rescue::ecat
