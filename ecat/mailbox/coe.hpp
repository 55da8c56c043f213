// CANopen over EtherCAT (ETG.1000.6 section 5.6.2, SDO protocol of CiA 301): the CoE header and
// SDO requests/responses in a mailbox, encoded and decoded byte by byte. Used by the master
// (client) and by the simulated drives' SDO server.
//
//   mailbox header (6, type 3 = CoE) | CoE header (2): number [8:0], service [15:12] |
//   SDO (8): command byte, index u16, subindex u8, 4 bytes (expedited data, complete size or
//            abort code) | normal-transfer data ...
//   segments: command byte, then the segment data (at least 7 bytes, n = unused ones)
//
// Command byte (client = request, service 2; server = response, service 3):
//   download initiate  req 001 0 n n e s   resp 011 00000
//   download segment   req 000 t n n n c   resp 001 t 0000
//   upload initiate    req 010 0 0000      resp 010 0 n n e s
//   upload segment     req 011 t 0000      resp 000 t n n n c
//   abort              100 00000 (both directions), u32 abort code in bytes 4..7
// Bit 4 of an initiate request is "complete access" (whole object from subindex 0 or 1); the upload
// response mirrors it (0x51 for a normal one, as slaves answer SOEM's 0x50).
//
// decode() takes untrusted bytes (a mailbox message): every length is checked against the
// mailbox length, and the sizes an SDO announces against the bytes present.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/mailbox/mailbox.hpp"

namespace rescue::ecat::coe {

constexpr std::size_t kCoeHeaderSize = 2;
constexpr std::size_t kSdoHeaderSize = 8;            // command, index, subindex, 4 bytes
constexpr std::size_t kSdoInitiateSize = kCoeHeaderSize + kSdoHeaderSize;  // 10: mailbox length of an expedited SDO
constexpr std::size_t kSegmentHeaderSize = 1;
constexpr std::size_t kMinSegmentData = 7;           // segments are padded to 7 data bytes
constexpr std::size_t kMaxExpeditedSize = 4;

enum class Service : std::uint8_t {
  emergency = 1,
  sdo_request = 2,
  sdo_response = 3,
  tx_pdo = 4,
  rx_pdo = 5,
  tx_pdo_remote_request = 6,
  rx_pdo_remote_request = 7,
  sdo_information = 8,
};

enum class SdoKind : std::uint8_t {
  download_initiate_request,
  download_initiate_response,
  download_segment_request,
  download_segment_response,
  upload_initiate_request,
  upload_initiate_response,
  upload_segment_request,
  upload_segment_response,
  abort,
};

// SDO abort codes (CiA 301 table 22, ETG.1000.6 table 41).
namespace abort_code {
constexpr std::uint32_t kToggleBit = 0x05030000;
constexpr std::uint32_t kTimeout = 0x05040000;
constexpr std::uint32_t kUnknownCommand = 0x05040001;
constexpr std::uint32_t kOutOfMemory = 0x05040005;
constexpr std::uint32_t kUnsupportedAccess = 0x06010000;
constexpr std::uint32_t kWriteOnly = 0x06010001;
constexpr std::uint32_t kReadOnly = 0x06010002;
constexpr std::uint32_t kSubindex0MustBeZero = 0x06010003;
constexpr std::uint32_t kCompleteAccessUnsupported = 0x06010004;
constexpr std::uint32_t kObjectDoesNotExist = 0x06020000;
constexpr std::uint32_t kCannotBeMapped = 0x06040041;
constexpr std::uint32_t kPdoLengthExceeded = 0x06040042;
constexpr std::uint32_t kParameterIncompatible = 0x06040043;
constexpr std::uint32_t kDeviceIncompatible = 0x06040047;
constexpr std::uint32_t kHardwareError = 0x06060000;
constexpr std::uint32_t kLengthMismatch = 0x06070010;
constexpr std::uint32_t kLengthTooHigh = 0x06070012;
constexpr std::uint32_t kLengthTooLow = 0x06070013;
constexpr std::uint32_t kSubindexDoesNotExist = 0x06090011;
constexpr std::uint32_t kValueRange = 0x06090030;
constexpr std::uint32_t kValueTooHigh = 0x06090031;
constexpr std::uint32_t kValueTooLow = 0x06090032;
constexpr std::uint32_t kMaxBelowMin = 0x06090036;
constexpr std::uint32_t kGeneralError = 0x08000000;
constexpr std::uint32_t kCannotTransfer = 0x08000020;
constexpr std::uint32_t kCannotTransferLocalControl = 0x08000021;
constexpr std::uint32_t kCannotTransferInState = 0x08000022;
constexpr std::uint32_t kNoObjectDictionary = 0x08000023;
}  // namespace abort_code

// One SDO message, decoded or to encode. Which fields matter depends on `kind`:
//   initiate: index, subindex, complete_access (requests), expedited, size_indicated, size
//             (expedited: data bytes 1..4; normal: the complete size), data (expedited bytes or
//             the normal-transfer bytes in this mailbox);
//   segment:  toggle, last_segment, data;  abort: index, subindex, abort_code.
struct Sdo {
  SdoKind kind{SdoKind::upload_initiate_request};
  std::uint16_t index{0};
  std::uint8_t subindex{0};
  bool complete_access{false};
  bool expedited{false};
  bool size_indicated{false};
  std::uint32_t size{0};
  bool toggle{false};
  bool last_segment{false};
  std::uint32_t abort_code{0};
  ConstByteSpan data{};
};

struct Emergency {
  std::uint16_t error_code{0};
  std::uint8_t error_register{0};
  std::uint8_t manufacturer[5]{};
};

// A decoded CoE message: the mailbox header, the CoE header and, for SDO services, the SDO.
struct Message {
  mbx::Header mailbox{};
  Service service{Service::sdo_request};
  std::uint16_t number{0};  // PDO number / 0
  Sdo sdo{};                // sdo_request / sdo_response
  Emergency emergency{};    // emergency
  ConstByteSpan payload{};  // bytes after the CoE header (all services)
};

// Decodes a CoE mailbox message (mailbox header included). Errors: those of mbx::decode, then
// unsupported "not a CoE mailbox", truncated "coe header" / "sdo header" (fewer than 8 SDO bytes)
// / "emergency", unsupported "sdo command" (block transfer or a specifier that does not exist in
// that direction; detail0 = specifier). Normal-transfer bytes past the announced complete size
// are padding and are left out of Sdo::data.
Result<Message> decode(ConstByteSpan mailbox) noexcept;
// Decodes the SDO part only (bytes after the CoE header) of a request or a response.
Result<Sdo> decode_sdo(ConstByteSpan sdo_bytes, Service service) noexcept;

// Encodes `sdo` as a whole mailbox message into `out`: the mailbox header fields come from
// `mailbox` (its length and type are set here), the CoE service from the kind. Returns the number
// of bytes written (6 + mailbox length). Errors: invalid_argument for an expedited transfer of 0
// or more than 4 bytes, capacity_exceeded when `out` is too short.
Result<std::size_t> encode(ByteSpan out, const mbx::Header& mailbox, const Sdo& sdo) noexcept;

// Shorthands for the common messages (all through encode()).
Sdo upload_request(std::uint16_t index, std::uint8_t subindex, bool complete_access = false) noexcept;
Sdo download_request(std::uint16_t index, std::uint8_t subindex, ConstByteSpan data) noexcept;  // expedited when <= 4 bytes
Sdo upload_response(std::uint16_t index, std::uint8_t subindex, ConstByteSpan data) noexcept;   // expedited when <= 4 bytes
Sdo download_response(std::uint16_t index, std::uint8_t subindex) noexcept;
Sdo abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code) noexcept;

// Whether `kind` travels as an SDO request (client -> server) or response.
constexpr bool is_request(SdoKind kind) noexcept {
  return kind == SdoKind::download_initiate_request || kind == SdoKind::download_segment_request ||
         kind == SdoKind::upload_initiate_request || kind == SdoKind::upload_segment_request;
}

const char* to_string(SdoKind kind) noexcept;
const char* explain_abort_code(std::uint32_t code) noexcept;

}  // namespace rescue::ecat::coe
