// Authentication of the UDP protocol (docs/protocol.md "Authentication") and the pre-shared key
// file. The tag is libsodium's crypto_auth (HMAC-SHA-512-256) over the header and the payload; no
// cryptography is written here, only the calls. The key file holds the 32-byte key as 64 hex
// digits and a newline; it must not be readable by group or others.
#pragma once

#include <cstddef>

#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "hal/files/durable_file.hpp"

namespace rescue::app::protocol {

// sodium_init(), once per process, before any other call here (idempotent).
Status init_crypto() noexcept;

// Encodes `message` (header fields other than payload_length taken from message.header), appends
// the tag under `key`; returns the datagram's length.
Result<std::size_t> seal(const Message& message, const Key& key, ByteSpan out) noexcept;

// The tag of a parsed frame, in constant time. Error checksum: it does not verify.
Status verify_frame(const FrameView& frame, const Key& key) noexcept;

// Reads a key file. Errors name the cause: not_found, permission_denied ("readable by group or
// others"; detail0 = the mode bits), malformed (not 64 hex digits), io_error (errno in detail0).
Result<Key> load_key_file(const char* path) noexcept;

// Creates a new key file with a random key (randombytes_buf), mode 0600; refuses to overwrite
// (Errc::busy when the file exists).
Status create_key_file(const char* path) noexcept;

// The default key file: operator.key in the state directory (hal::resolve_state_dir).
Result<hal::PathBuffer> default_key_path() noexcept;

}  // namespace rescue::app::protocol
