// Numbers of the two capture file formats Wireshark reads, shared by the writer and the reader.
//
// pcapng (IETF draft-ietf-opsawg-pcapng): a sequence of blocks, each
//   u32 block type | u32 total length | body | u32 total length (again)
// with lengths a multiple of 4 and multi-byte fields in the byte order of the section, which the
// Section Header Block's byte-order magic announces. Options inside a body are
//   u16 code | u16 length | value padded to 4 bytes, ended by code 0 (opt_endofopt).
//
//   SHB  0x0A0D0D0A  magic u32, major u16 = 1, minor u16, section length i64, options
//   IDB  1           link type u16, reserved u16, snap length u32, options (if_tsresol ...)
//   EPB  6           interface u32, timestamp high u32, low u32, captured len u32, original len u32,
//                    data padded to 4, options (epb_flags: direction)
//   SPB  3           original len u32, data (interface 0, no timestamp)
//   PB   2           obsolete: interface u16, drops u16, timestamp high/low, captured, original, data
//
// classic pcap (draft-ietf-opsawg-pcap): a 24-byte file header
//   magic u32, major u16 = 2, minor u16, thiszone i32, sigfigs u32, snap length u32, link type u32
// then per packet ts seconds u32, ts fraction u32 (us or ns by magic), captured u32, original u32,
// data. The byte order is the writer's, recognised by the magic.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rescue::ecat::capture {

constexpr std::uint16_t kLinkTypeEthernet = 1;

// --- pcapng -------------------------------------------------------------------------------------
constexpr std::uint32_t kBlockSectionHeader = 0x0A0D0D0A;
constexpr std::uint32_t kBlockInterfaceDescription = 0x00000001;
constexpr std::uint32_t kBlockPacketObsolete = 0x00000002;
constexpr std::uint32_t kBlockSimplePacket = 0x00000003;
constexpr std::uint32_t kBlockEnhancedPacket = 0x00000006;
constexpr std::uint32_t kByteOrderMagic = 0x1A2B3C4D;
constexpr std::uint16_t kPcapngMajor = 1;
constexpr std::uint16_t kPcapngMinor = 0;

constexpr std::size_t kBlockHeaderSize = 8;   // type + total length
constexpr std::size_t kBlockTrailerSize = 4;  // total length again
constexpr std::size_t kMinBlockSize = kBlockHeaderSize + kBlockTrailerSize;
constexpr std::size_t kShbFixedBody = 16;     // magic, versions, section length
constexpr std::size_t kIdbFixedBody = 8;      // link type, reserved, snap length
constexpr std::size_t kEpbFixedBody = 20;     // interface, ts high, ts low, captured, original
constexpr std::size_t kSpbFixedBody = 4;      // original length
constexpr std::size_t kPbFixedBody = 20;      // interface u16, drops u16, ts high, ts low, captured, original

// Option codes.
constexpr std::uint16_t kOptEndOfOptions = 0;
constexpr std::uint16_t kOptShbUserApplication = 4;
constexpr std::uint16_t kOptIfName = 2;
constexpr std::uint16_t kOptIfTimestampResolution = 9;  // u8: 10^-n s, or 2^-n s when bit 7 is set
constexpr std::uint16_t kOptIfFcsLength = 13;           // u8: bytes of FCS at the end of each packet
constexpr std::uint16_t kOptIfTimestampOffset = 14;     // i64 seconds added to every timestamp
constexpr std::uint16_t kOptEpbFlags = 2;               // u32: [1:0] direction 0 unknown, 1 in, 2 out
constexpr std::uint32_t kEpbFlagsDirectionMask = 0x3;
constexpr std::uint8_t kTsresolMicroseconds = 6;        // the default when if_tsresol is absent
constexpr std::uint8_t kTsresolNanoseconds = 9;
constexpr std::uint8_t kTsresolBinaryFlag = 0x80;

// --- classic pcap -------------------------------------------------------------------------------
constexpr std::uint32_t kPcapMagicMicroseconds = 0xA1B2C3D4;
constexpr std::uint32_t kPcapMagicNanoseconds = 0xA1B23C4D;
constexpr std::uint16_t kPcapMajor = 2;
constexpr std::size_t kPcapFileHeaderSize = 24;
constexpr std::size_t kPcapRecordHeaderSize = 16;
// Link-type field: low 16 bits the link type; bit 26 says bits 28..31 hold the FCS length in
// 16-bit words (libpcap's LT_FCS_LENGTH_PRESENT / LT_FCS_LENGTH).
constexpr std::uint32_t kPcapFcsPresentFlag = 0x04000000;
constexpr unsigned kPcapFcsLengthShift = 28;

// A packet longer than this is not a frame of this product (Wireshark's own limit is 256 KiB).
constexpr std::uint32_t kMaxPacketLength = 262144;

}  // namespace rescue::ecat::capture

namespace rescue::ecat {

// Which way a captured frame went, as pcapng's epb_flags encodes it.
enum class FrameDirection : std::uint8_t { unknown = 0, inbound = 1, outbound = 2 };

}  // namespace rescue::ecat
