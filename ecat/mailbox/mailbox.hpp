// EtherCAT mailbox (ETG.1000.4 section 5.6 / ETG.1000.6 section 5.6): the 6-byte header every
// mailbox message starts with, in SyncManager 0 (master -> slave) and 1 (slave -> master).
//
//   bytes 0..1  length: bytes of data after this header
//   bytes 2..3  address: station address of the source (slave -> master) or 0 / destination
//   byte  4     channel [5:0], priority [7:6]
//   byte  5     type [3:0] (kMailboxType*), counter [6:4] (1..7, 0 = not used), reserved [7]
//
// A mailbox SyncManager is as long as its configured size; the header's length says how much of
// it is the message. decode() checks that length against the buffer. Mailbox error replies
// (type 0) carry a u16 type (1) and a u16 detail code (kMailboxError*).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"

namespace rescue::ecat::mbx {

constexpr std::size_t kHeaderSize = 6;

enum class Type : std::uint8_t { error = 0x0, aoe = 0x1, eoe = 0x2, coe = 0x3, foe = 0x4, soe = 0x5, voe = 0xF };

// Mailbox error reply detail codes (ETG.1000.6 table 30).
namespace error_code {
constexpr std::uint16_t kSyntax = 0x0001;
constexpr std::uint16_t kUnsupportedProtocol = 0x0002;
constexpr std::uint16_t kInvalidChannel = 0x0003;
constexpr std::uint16_t kServiceNotSupported = 0x0004;
constexpr std::uint16_t kInvalidHeader = 0x0005;
constexpr std::uint16_t kSizeTooShort = 0x0006;
constexpr std::uint16_t kNoMoreMemory = 0x0007;
constexpr std::uint16_t kInvalidSize = 0x0008;
}  // namespace error_code
constexpr std::size_t kErrorReplyLength = 4;

struct Header {
  std::uint16_t length{0};
  std::uint16_t address{0};
  std::uint8_t channel{0};   // 0..63
  std::uint8_t priority{0};  // 0..3
  Type type{Type::coe};
  std::uint8_t counter{0};   // 0..7
};

// A decoded mailbox message: its header and a view of its `length` data bytes.
struct Message {
  Header header{};
  ConstByteSpan data{};
};

// Next counter value after `counter`: 1..7 wrapping to 1 (0 is "not used").
constexpr std::uint8_t next_counter(std::uint8_t counter) noexcept {
  return static_cast<std::uint8_t>(counter >= 7 ? 1 : counter + 1);
}

// Decodes the header at the start of `bytes` (a whole mailbox SyncManager or less). Errors:
// truncated "mailbox header" (fewer than 6 bytes), truncated "mailbox length" (length past the
// buffer; detail0 = length, detail1 = bytes available after the header).
Result<Message> decode(ConstByteSpan bytes) noexcept;

// Writes the 6-byte header into `out` (invalid_argument for channel > 63, priority > 3,
// counter > 7; capacity_exceeded when `out` is shorter than 6 + header.length).
Status encode_header(ByteSpan out, const Header& header) noexcept;

// A whole mailbox error reply (header + 4 bytes) into `out`; returns its size.
Result<std::size_t> encode_error_reply(ByteSpan out, std::uint16_t address, std::uint16_t detail) noexcept;
// The detail code of a decoded error reply (malformed if it is not one).
Result<std::uint16_t> decode_error_reply(const Message& message) noexcept;

const char* to_string(Type type) noexcept;
const char* explain_error_code(std::uint16_t detail) noexcept;

}  // namespace rescue::ecat::mbx
