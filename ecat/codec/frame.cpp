#include "ecat/codec/frame.hpp"

#include <cstring>

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kEcatLengthMask = 0x07FF;
constexpr std::uint16_t kMoreFollows = 0x8000;

std::uint32_t u32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

}  // namespace

template <typename B>
Result<BasicFrameView<B>> BasicFrameView<B>::parse(Span<B> frame) noexcept {
  const std::size_t size = frame.size();
  const std::uint8_t* p = frame.data();

  if (size < kEthernetHeaderSize) return make_error(Errc::truncated, "ethernet header", kFrameLevel, 0);
  // A capture may keep the 4-byte FCS after the payload; more than that is not Ethernet.
  if (size > kMaxFrameSize + kVlanTagSize + 4) return make_error(Errc::malformed, "frame too long", kFrameLevel, u32(size));
  std::size_t offset = 12;
  std::uint16_t ether_type = load_be16(p + offset);
  bool vlan_tagged = false;
  std::uint16_t vlan_tci = 0;
  if (ether_type == kEtherTypeVlan) {
    if (size < offset + kVlanTagSize + 2) return make_error(Errc::truncated, "vlan tag", kFrameLevel, u32(offset));
    vlan_tagged = true;
    vlan_tci = load_be16(p + offset + 2);
    offset += kVlanTagSize;
    ether_type = load_be16(p + offset);
  }
  if (ether_type != kEtherTypeEtherCAT) return make_error(Errc::unsupported, "not EtherCAT", kFrameLevel, u32(offset));
  offset += 2;
  auto ecat = parse_ecat(frame, offset);
  if (!ecat.ok()) return ecat.error();
  FrameHeader& h = ecat.value().header_;
  std::memcpy(h.destination.data(), p, 6);
  std::memcpy(h.source.data(), p + 6, 6);
  h.vlan_tagged = vlan_tagged;
  h.vlan_tci = vlan_tci;
  return ecat;
}

template <typename B>
Result<BasicFrameView<B>> BasicFrameView<B>::parse_ecat(Span<B> frame, std::size_t ecat_offset) noexcept {
  BasicFrameView view;
  view.frame_ = frame;
  FrameHeader& h = view.header_;
  const std::size_t size = frame.size();
  const std::uint8_t* p = frame.data();
  std::size_t offset = ecat_offset;

  if (offset > size || size - offset < kEcatHeaderSize) return make_error(Errc::truncated, "ecat header", kFrameLevel, u32(offset));
  const std::uint16_t ecat_word = load_le16(p + offset);
  h.ecat_offset = offset;
  h.ecat_length = static_cast<std::uint16_t>(ecat_word & kEcatLengthMask);
  h.ecat_type = static_cast<std::uint8_t>(ecat_word >> 12);
  if (h.ecat_type != kEcatTypeDatagrams) return make_error(Errc::unsupported, "ecat type", kFrameLevel, u32(offset));
  offset += kEcatHeaderSize;
  if (h.ecat_length > size - offset) return make_error(Errc::truncated, "ecat length", kFrameLevel, u32(h.ecat_offset));
  // Bytes after the EtherCAT payload (Ethernet padding, a captured FCS) are not ours to check.
  const std::size_t payload_end = offset + h.ecat_length;

  std::uint32_t index = 0;
  bool more = true;
  while (more) {
    if (index >= kMaxDatagramsPerFrame) return make_error(Errc::malformed, "datagram count", index, u32(offset));
    if (payload_end - offset < kDatagramHeaderSize) return make_error(Errc::truncated, "datagram header", index, u32(offset));
    if (!is_valid_command(p[offset])) return make_error(Errc::malformed, "datagram command", index, u32(offset));
    const std::uint16_t len_word = load_le16(p + offset + 6);
    const std::size_t data_length = len_word & kEcatLengthMask;
    if (payload_end - offset - kDatagramHeaderSize < data_length + kWkcSize) {
      return make_error(Errc::truncated, "datagram length", index, u32(offset + 6));
    }
    more = (len_word & kMoreFollows) != 0;
    offset += kDatagramOverhead + data_length;
    ++index;
  }
  // Padding: fewer bytes than a datagram needs, all zero. Anything else is garbage.
  const std::size_t trailing = payload_end - offset;
  bool padding = trailing < kDatagramOverhead;
  for (std::size_t i = offset; padding && i < payload_end; ++i) padding = p[i] == 0;
  if (!padding) return make_error(Errc::malformed, "bytes after last datagram", index, u32(offset));
  h.padding = static_cast<std::uint16_t>(trailing);
  h.datagram_count = index;
  return view;
}

template class BasicFrameView<const std::uint8_t>;
template class BasicFrameView<std::uint8_t>;

void FrameBuilder::reset(const MacAddress& source, const MacAddress& destination) noexcept {
  std::memcpy(buffer_.data(), destination.data(), 6);
  std::memcpy(buffer_.data() + 6, source.data(), 6);
  store_be16(buffer_.data() + 12, kEtherTypeEtherCAT);
  size_ = kEthernetHeaderSize + kEcatHeaderSize;
  count_ = 0;
  last_header_offset_ = 0;
}

std::size_t FrameBuilder::remaining_data_capacity() const noexcept {
  const std::size_t used = size_ + kDatagramOverhead;
  return used >= kMaxFrameSize ? 0 : kMaxFrameSize - used;
}

Result<DatagramSlot> FrameBuilder::add(Command command, std::uint8_t index, std::uint32_t address,
                                       std::uint16_t length, ConstByteSpan data, std::uint16_t irq,
                                       std::uint16_t wkc) noexcept {
  if (!is_valid_command(static_cast<std::uint8_t>(command))) {
    return make_error(Errc::invalid_argument, "command", u32(count_));
  }
  if (length > kMaxDatagramDataLength) return make_error(Errc::invalid_argument, "datagram length", u32(count_), length);
  if (!data.empty() && data.size() != length) {
    return make_error(Errc::invalid_argument, "data size differs from length", u32(count_), u32(data.size()));
  }
  if (size_ + kDatagramOverhead + length > kMaxFrameSize) {
    return make_error(Errc::capacity_exceeded, "frame full", u32(count_), length);
  }

  std::uint8_t* h = buffer_.data() + size_;
  h[0] = static_cast<std::uint8_t>(command);
  h[1] = index;
  store_le32(h + 2, address);
  store_le16(h + 6, length);  // more-follows is set by the next add()
  store_le16(h + 8, irq);
  if (data.empty()) {
    std::memset(h + kDatagramHeaderSize, 0, length);
  } else {
    std::memcpy(h + kDatagramHeaderSize, data.data(), length);
  }
  store_le16(h + kDatagramHeaderSize + length, wkc);

  if (count_ > 0) {
    std::uint8_t* prev = buffer_.data() + last_header_offset_;
    store_le16(prev + 6, static_cast<std::uint16_t>(load_le16(prev + 6) | kMoreFollows));
  }
  DatagramSlot slot{size_, size_ + kDatagramHeaderSize, length};
  last_header_offset_ = size_;
  size_ += kDatagramOverhead + length;
  ++count_;
  return slot;
}

ConstByteSpan FrameBuilder::finish() noexcept {
  const std::size_t ecat_length = size_ - kEthernetHeaderSize - kEcatHeaderSize;
  store_le16(buffer_.data() + kEthernetHeaderSize,
             static_cast<std::uint16_t>(ecat_length | (std::uint16_t{kEcatTypeDatagrams} << 12)));
  std::size_t total = size_;
  if (total < kMinFrameSize) {
    std::memset(buffer_.data() + total, 0, kMinFrameSize - total);
    total = kMinFrameSize;
  }
  return {buffer_.data(), total};
}

}  // namespace rescue::ecat
