// CoE SDO Information (ETG.1000.6 section 5.6.3), the master's side: what lets `ctl sdos` list a
// slave's object dictionary instead of knowing it beforehand (SOEM's ec_readODlist /
// ec_readODdescription / ec_readOE, IgH's `ethercat sdos`). Encoded and decoded byte by byte;
// every decoder takes untrusted bytes and checks each length against the bytes present.
//
//   CoE header (service 8) | opcode [6:0] + incomplete [7] | reserved | fragments left u16 | data
//
//   Get OD List req (1): list type u16      -> resp (2): list type u16, indexes u16 ...
//   Get Object Description req (3): index   -> resp (4): index, data type u16, max subindex u8,
//        object code u8 (7 VAR, 8 ARRAY, 9 RECORD), name (the rest)
//   Get Entry Description req (5): index, subindex, value info u8 (0: only the name)
//                                           -> resp (6): index, subindex, value info, data type u16,
//        bit length u16, access u16, name (the rest)
//   SDO Info Error (7): abort code u32
// A response longer than the slave's SM1 mailbox comes in fragments, each with the number still to
// come; the data of all of them, after each one's 4-byte header, is the response's data.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/mailbox/mailbox.hpp"

namespace rescue::ecat::coe::info {

constexpr std::uint8_t kGetOdListRequest = 0x01;
constexpr std::uint8_t kGetOdListResponse = 0x02;
constexpr std::uint8_t kGetObjectDescriptionRequest = 0x03;
constexpr std::uint8_t kGetObjectDescriptionResponse = 0x04;
constexpr std::uint8_t kGetEntryDescriptionRequest = 0x05;
constexpr std::uint8_t kGetEntryDescriptionResponse = 0x06;
constexpr std::uint8_t kErrorRequest = 0x07;
constexpr std::uint8_t kIncomplete = 0x80;
constexpr std::uint8_t kOpcodeMask = 0x7F;
constexpr std::size_t kInfoHeaderSize = 4;      // opcode, reserved, fragments left
constexpr std::uint16_t kListAll = 1;           // Get OD List: every object
constexpr std::size_t kObjectDescriptionHead = 6;
constexpr std::size_t kEntryDescriptionHead = 10;

// Whether `opcode` is one of the three requests this master sends.
constexpr bool is_request(std::uint8_t opcode) noexcept {
  return opcode == kGetOdListRequest || opcode == kGetObjectDescriptionRequest || opcode == kGetEntryDescriptionRequest;
}

// One fragment of a response (the bytes after the CoE header).
struct Fragment {
  std::uint8_t opcode{0};  // without the incomplete bit
  bool incomplete{false};
  std::uint16_t fragments_left{0};
  ConstByteSpan data{};
};
// Errors: truncated "sdo information header" (fewer than 4 bytes).
Result<Fragment> decode_fragment(ConstByteSpan coe_payload) noexcept;

// Encodes request `opcode` (kGetOdListRequest: `index` is the list type; kGetObjectDescriptionRequest:
// the object; kGetEntryDescriptionRequest: the object and `subindex`, value info 0) as a whole
// mailbox message into `out`; returns its bytes. Errors: invalid_argument for another opcode,
// capacity_exceeded when `out` is too short.
Result<std::size_t> encode_request(ByteSpan out, const mbx::Header& mailbox, std::uint8_t opcode, std::uint16_t index,
                                   std::uint8_t subindex) noexcept;

// A Get Object Description response's data. Errors: truncated "object description".
struct ObjectDescription {
  std::uint16_t index{0};
  std::uint16_t data_type{0};
  std::uint8_t max_subindex{0};
  std::uint8_t object_code{0};
  ConstByteSpan name{};
};
Result<ObjectDescription> decode_object_description(ConstByteSpan data) noexcept;

// A Get Entry Description response's data (asked with value info 0: the name follows the access).
// Errors: truncated "entry description".
struct EntryDescription {
  std::uint16_t index{0};
  std::uint8_t subindex{0};
  std::uint8_t value_info{0};
  std::uint16_t data_type{0};
  std::uint16_t bit_length{0};
  std::uint16_t access{0};
  ConstByteSpan name{};
};
Result<EntryDescription> decode_entry_description(ConstByteSpan data) noexcept;

// A Get OD List response's data: the list type, then `count` indexes. Errors: truncated "od list"
// (no list type), malformed "od list length" (an odd number of bytes).
struct OdList {
  std::uint16_t list_type{0};
  std::size_t count{0};
  ConstByteSpan indexes{};  // 2 * count bytes
  std::uint16_t index(std::size_t i) const noexcept;
};
Result<OdList> decode_od_list(ConstByteSpan data) noexcept;

// Names, as IgH's `ethercat sdos` and ETG.1000.6 write them: "VAR", "ARRAY", "RECORD" (else "?");
// a CiA 301 basic data type ("UNSIGNED32", "VISIBLE_STRING"; "?" for others).
const char* object_code_name(std::uint8_t code) noexcept;
const char* data_type_name(std::uint16_t type) noexcept;
// The access bits as IgH prints them: read/write in PRE-OP, SAFE-OP, OP ("rwr-r-"); `out` >= 7 bytes.
void access_text(std::uint16_t access, char (&out)[7]) noexcept;

}  // namespace rescue::ecat::coe::info
