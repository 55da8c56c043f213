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
#include "hal/files/trusted_file.hpp"

namespace rescue::app::protocol {

// sodium_init(), once per process, before any other call here (idempotent).
Status init_crypto() noexcept;

// Encodes `message` (header fields other than payload_length taken from message.header), appends
// the tag under `key`; returns the datagram's length.
Result<std::size_t> seal(const Message& message, const Key& key, ByteSpan out) noexcept;

// The tag of a parsed frame, in constant time. Error checksum: it does not verify.
Status verify_frame(const FrameView& frame, const Key& key) noexcept;

// A new epoch for the replay window (replay_window.hpp): 64 random bits (randombytes_buf), never 0.
std::uint64_t new_epoch() noexcept;

// Reads a key file, trusted only as OpenSSH's StrictModes would (hal/files/trusted_file.hpp): it and
// every directory above it owned by this user or root, not writable by group or others, the key not
// readable by them; a regular file (a FIFO or device is refused at once). Errors: not_found,
// permission_denied, invalid_argument (not a regular file), malformed (not 64 hex digits),
// io_error; `why` then holds one sentence naming the path, the cause and the fix.
Result<Key> load_key_file(const char* path, hal::FileProblem& why) noexcept;

// Creates a new key file with a random key (randombytes_buf), mode 0600; refuses to overwrite
// (Errc::busy when the file exists).
Status create_key_file(const char* path) noexcept;

// The default key file: operator.key in the state directory (hal::resolve_state_dir).
Result<hal::PathBuffer> default_key_path() noexcept;

}  // namespace rescue::app::protocol
