#include "ecat/capture/captured_link.hpp"

#include "core/base/endian.hpp"

namespace rescue::ecat {
namespace {

std::uint32_t u32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

Result<FrameView> decode_cooked(ConstByteSpan packet, std::size_t header_size, std::size_t protocol_offset) noexcept {
  if (packet.size() < header_size) return make_error(Errc::truncated, "sll header", kFrameLevel, 0);
  std::uint16_t protocol = load_be16(packet.data() + protocol_offset);
  std::size_t offset = header_size;
  if (protocol == kEtherTypeVlan) {
    if (packet.size() - offset < kVlanTagSize) return make_error(Errc::truncated, "sll vlan tag", kFrameLevel, u32(offset));
    protocol = load_be16(packet.data() + offset + 2);
    offset += kVlanTagSize;
  }
  if (protocol != kEtherTypeEtherCAT) return make_error(Errc::unsupported, "not EtherCAT", kFrameLevel, u32(protocol_offset));
  return FrameView::parse_ecat(packet, offset);
}

}  // namespace

bool is_supported_link_type(std::uint16_t link_type) noexcept {
  return link_type == capture::kLinkTypeEthernet || link_type == capture::kLinkTypeLinuxSll ||
         link_type == capture::kLinkTypeLinuxSll2;
}

Result<FrameView> decode_captured_frame(std::uint16_t link_type, ConstByteSpan packet) noexcept {
  switch (link_type) {
    case capture::kLinkTypeEthernet:
      return FrameView::parse(packet);
    case capture::kLinkTypeLinuxSll:
      return decode_cooked(packet, capture::kSllHeaderSize, capture::kSllProtocolOffset);
    case capture::kLinkTypeLinuxSll2:
      return decode_cooked(packet, capture::kSll2HeaderSize, capture::kSll2ProtocolOffset);
    default:
      return make_error(Errc::unsupported, "link type", kFrameLevel, link_type);
  }
}

}  // namespace rescue::ecat
