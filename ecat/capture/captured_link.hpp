// The EtherCAT frame inside a captured packet, by the capture's link type. The bytes are untrusted:
// every header length is checked before a field is read, and errors are values.
//
//   link type 1    Ethernet II (optionally one 802.1Q tag): FrameView::parse
//   link type 113  Linux cooked capture v1 (SLL, what `tcpdump -i any` writes), 16-byte header:
//                  u16 packet type | u16 ARPHRD type | u16 address length | u8 address[8] |
//                  u16 protocol (EtherType), all big-endian
//   link type 276  Linux cooked capture v2 (SLL2, `tshark -i any`), 20-byte header:
//                  u16 protocol (EtherType) | u16 reserved | u32 interface index |
//                  u16 ARPHRD type | u8 packet type | u8 address length | u8 address[8]
// A cooked protocol of 0x8100 means a 4-byte 802.1Q tag (TCI, then the EtherType) precedes the
// payload. With EtherType 0x88A4 the payload is the EtherCAT header and datagrams, decoded by
// FrameView::parse_ecat with the same checks as an Ethernet frame.
//
// Error values (Error::what, code; detail0 kFrameLevel or the datagram, detail1 the byte offset in
// the packet):
//   "link type"     unsupported  any other link type (detail1 = the link type)
//   "sll header"    truncated    fewer bytes than the cooked header
//   "sll vlan tag"  truncated    a cooked 802.1Q tag cut short
//   "not EtherCAT"  unsupported  another EtherType: callers skip the frame
//   any error of FrameView::parse / parse_ecat for the EtherCAT part
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/capture/capture_format.hpp"
#include "ecat/codec/frame.hpp"

namespace rescue::ecat {

namespace capture {
constexpr std::uint16_t kLinkTypeLinuxSll = 113;
constexpr std::uint16_t kLinkTypeLinuxSll2 = 276;
constexpr std::size_t kSllHeaderSize = 16;
constexpr std::size_t kSll2HeaderSize = 20;
constexpr std::size_t kSllProtocolOffset = 14;
constexpr std::size_t kSll2ProtocolOffset = 0;
}  // namespace capture

// True for the link types decode_captured_frame reads.
bool is_supported_link_type(std::uint16_t link_type) noexcept;

// The EtherCAT frame in `packet`, captured on a link of `link_type`.
Result<FrameView> decode_captured_frame(std::uint16_t link_type, ConstByteSpan packet) noexcept;

}  // namespace rescue::ecat
