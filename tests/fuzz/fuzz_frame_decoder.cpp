// libFuzzer target: FrameView/MutableFrameView::parse on arbitrary bytes never reads outside them,
// and whatever it accepts is self-consistent and rebuilds: the datagrams and their zero padding
// (fewer than 12 bytes) tile the EtherCAT length exactly, more-follows is set on all but the last, a slave's in-place edits keep the frame
// parseable, and FrameBuilder given the decoded fields reproduces the EtherCAT bytes (apart from
// the reserved and circulating bits, which the builder never sets).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "ecat/codec/frame.hpp"

namespace {

using namespace rescue;        // NOLINT(google-build-using-namespace)
using namespace rescue::ecat;  // NOLINT(google-build-using-namespace)

void check(bool condition) {
  if (!condition) std::abort();
}

void check_consistent(const FrameView& view, std::size_t size) {
  const FrameHeader& h = view.header();
  check(h.ecat_end() <= size);
  check(h.datagram_count >= 1 && h.datagram_count <= kMaxDatagramsPerFrame);
  std::size_t covered = 0;
  std::uint32_t n = 0;
  unsigned sum = 0;
  for (const DatagramView d : view) {
    check(d.index_in_frame() == n);
    check(is_valid_command(static_cast<std::uint8_t>(d.command())));
    check(d.more_follows() == (n + 1 < h.datagram_count));
    check(d.raw() >= view.bytes().data() && d.raw() + d.wire_size() <= view.bytes().data() + h.ecat_end());
    for (const std::uint8_t byte : d.data()) sum += byte;
    sum += d.wkc() + d.irq() + d.adp() + d.ado();
    covered += d.wire_size();
    ++n;
  }
  (void)sum;
  check(n == h.datagram_count);
  check(h.padding < kDatagramOverhead);
  check(covered + h.padding == h.ecat_length);
  for (std::size_t i = h.ecat_end() - h.padding; i < h.ecat_end(); ++i) check(view.bytes()[i] == 0);
}

// Rebuilds the frame from its decoded fields and compares the EtherCAT part.
void check_rebuilds(const FrameView& view) {
  const FrameHeader& h = view.header();
  if (h.vlan_tagged) return;  // the builder writes untagged frames only
  FrameBuilder b;
  b.reset(h.source, h.destination);
  for (const DatagramView d : view) {
    const auto slot = b.add(d.command(), d.index(), d.address(), d.length(), d.data(), d.irq(), d.wkc());
    if (!slot.ok()) {
      // Only a frame longer than 1514 bytes (possible when a captured FCS is counted in) may not
      // fit the builder's buffer again.
      check(h.ecat_end() > kMaxFrameSize);
      return;
    }
  }
  const ConstByteSpan rebuilt = b.finish();
  const std::uint8_t* original = view.bytes().data();
  check(rebuilt.size() + h.padding >= h.ecat_end());  // the builder never writes the padding
  check(std::memcmp(rebuilt.data(), original, kEthernetHeaderSize) == 0);                        // MACs, type
  const std::uint16_t rebuilt_word = static_cast<std::uint16_t>(load_le16(rebuilt.data() + 14) + h.padding);  // builder never pads
  check((rebuilt_word & 0xF7FFU) == (load_le16(original + 14) & 0xF7FFU));                     // reserved bit 11
  std::size_t at = kEthernetHeaderSize + kEcatHeaderSize;
  for (const DatagramView d : view) {
    check(std::memcmp(rebuilt.data() + at, original + at, 6) == 0);                      // cmd, idx, address
    constexpr std::uint16_t kLengthAndMore = 0x87FF;                                      // not reserved, not C
    check((load_le16(rebuilt.data() + at + 6) & kLengthAndMore) == (load_le16(original + at + 6) & kLengthAndMore));
    check(std::memcmp(rebuilt.data() + at + 8, original + at + 8, d.wire_size() - 8) == 0);  // irq, data, wkc
    at += d.wire_size();
  }
}

// What slaves do to a passing frame must keep it a valid frame with the same shape.
void check_in_place_edits(const std::uint8_t* data, std::size_t size, std::size_t datagrams) {
  static std::uint8_t copy[kMaxFrameSize + kVlanTagSize + 4];
  std::memcpy(copy, data, size);
  auto parsed = MutableFrameView::parse(ByteSpan(copy, size));
  check(parsed.ok());
  for (const MutableDatagramView d : parsed.value()) {
    d.set_adp(static_cast<std::uint16_t>(d.adp() + 1));
    d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 3));
    d.set_circulating(!d.circulating());
    if (!d.data().empty()) d.data()[0] ^= 0xFF;
  }
  const auto again = FrameView::parse(ConstByteSpan(copy, size));
  check(again.ok() && again.value().datagram_count() == datagrams);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto parsed = FrameView::parse(ConstByteSpan(data, size));
  if (!parsed.ok()) {
    const Error& e = parsed.error();
    check(e.what != nullptr && e.code != Errc::ok);
    check(e.detail0 == kFrameLevel || e.detail0 <= kMaxDatagramsPerFrame);
    check(e.detail1 <= size);
    return 0;
  }
  check_consistent(parsed.value(), size);
  check_rebuilds(parsed.value());
  check_in_place_edits(data, size, parsed.value().datagram_count());
  return 0;
}
