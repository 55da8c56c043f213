// Encoder and decoder of the UDP protocol (docs/protocol.md). Every field is written and read byte
// by byte, little-endian (core/base/endian.hpp); every length and offset is checked before a byte is
// read; every value is checked against its documented range. Authentication (the 32-byte tag) is
// computed and verified by protocol_auth.hpp with libsodium; this file only places it.
//
// Decoding a datagram is three steps, in this order (the socket handler's order):
//   1. parse_frame: structure only (sizes, magic, version, reserved bytes), no key needed;
//   2. verify_frame (protocol_auth.hpp): the tag over header + payload;
//   3. decode_payload: the type's payload and its ranges, then the replay check (replay_window.hpp),
//      so a malformed request takes no sender slot.
// An Error from steps 1 and 3 maps to the Rejection counted for it (rejection_of).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/app/links/protocol_messages.hpp"
#include "core/base/result.hpp"
#include "core/base/span.hpp"

namespace rescue::app::protocol {

// A datagram whose structure checked out; views into the caller's buffer.
struct FrameView {
  Header header{};
  ConstByteSpan signed_bytes{};  // header + payload: what the tag authenticates
  ConstByteSpan payload{};
  ConstByteSpan tag{};
};

// Structure of a received datagram. Errors: capacity_exceeded (oversized), malformed.
Result<FrameView> parse_frame(ConstByteSpan datagram) noexcept;

// The payload of `header.type`. Errors: unsupported (unknown type), malformed (length, reserved
// bytes, an unterminated name), out_of_range (a value outside its range).
Result<Message> decode_payload(const Header& header, ConstByteSpan payload) noexcept;

// Payload bytes of `message` (of message.header.type) into `out`; returns the length.
Result<std::size_t> encode_payload(const Message& message, ByteSpan out) noexcept;

// The header bytes (kHeaderSize) for `header` into `out`.
void encode_header(const Header& header, std::uint8_t* out) noexcept;

// Which counter an Error of parse_frame/decode_payload goes to.
Rejection rejection_of(const Error& error) noexcept;

// Copies `text` into a NUL-padded field (truncated so the last byte stays NUL).
template <std::size_t N>
void set_text(std::array<char, N>& field, const char* text) noexcept {
  field.fill('\0');
  for (std::size_t i = 0; i + 1 < N && text != nullptr && text[i] != '\0'; ++i) field[i] = text[i];
}

}  // namespace rescue::app::protocol
