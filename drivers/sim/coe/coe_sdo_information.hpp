// The CoE SDO Information service of a simulated drive (ETG.1000.6 section 5.6.3): what lets a
// master list the object dictionary (SOEM's `slaveinfo -sdo`, ec_readODlist / ec_readODdescription /
// ec_readOE) instead of knowing it beforehand. A pure function of (request, object dictionary).
//
//   CoE header (service 8) | opcode [6:0] + incomplete [7] | reserved | fragments left u16 | data
//
//   Get OD List req (1): list type u16      -> resp (2): list type u16, indexes u16 ...
//        list type 0: the five list lengths (1 all, 2 RxPDO-mappable, 3 TxPDO-mappable,
//        4 device replacement, 5 startup parameters); 1..5: that list's indexes, ascending
//   Get Object Description req (3): index   -> resp (4): index, data type u16, max subindex u8,
//        object code u8 (7 VAR, 8 ARRAY, 9 RECORD), name
//   Get Entry Description req (5): index, subindex, value info u8
//                                           -> resp (6): index, subindex, value info (0: no unit,
//        default, minimum or maximum follow), data type u16, bit length u16, access u16, name
//   anything wrong                          -> SDO Info Error (7): abort code u32 (object or
//        subindex missing, unknown opcode); a request too short for its opcode: mailbox error
//
// Object access bits: 0..2 readable in PRE-OP/SAFE-OP/OP, 3..5 writable in them, 6 RxPDO- and 7
// TxPDO-mappable. An object is PDO-mappable when the device's PDO mapping objects (0x1600.. and
// 0x1A00..) map it: the drives accept only their fixed mapping, so mappable and mapped coincide.
// Object codes and data types of the CiA 301 communication objects follow that standard (0x1018
// RECORD of IDENTITY 0x0023, PDO mappings RECORD of PDO_MAPPING 0x0021, 0x1C00 and the PDO
// assignments ARRAY); other objects with subindexes are ARRAYs when their entries share one type.
// Object names: subindex 0's name up to its colon ("RxPDO mapping: entries" -> "RxPDO mapping").
//
// A response longer than the SM1 mailbox is cut into fragments: each carries the number of
// fragments still to come and the incomplete bit; the first a GET OD LIST response's list type,
// the following only the rest of its indexes.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"
#include "drivers/sim/coe/object_dictionary.hpp"

namespace rescue::drivers {

namespace sdo_info {
constexpr std::uint8_t kGetOdListRequest = 0x01;
constexpr std::uint8_t kGetOdListResponse = 0x02;
constexpr std::uint8_t kGetObjectDescriptionRequest = 0x03;
constexpr std::uint8_t kGetObjectDescriptionResponse = 0x04;
constexpr std::uint8_t kGetEntryDescriptionRequest = 0x05;
constexpr std::uint8_t kGetEntryDescriptionResponse = 0x06;
constexpr std::uint8_t kErrorRequest = 0x07;
constexpr std::uint8_t kIncomplete = 0x80;
constexpr std::uint8_t kObjectCodeVar = 7;
constexpr std::uint8_t kObjectCodeArray = 8;
constexpr std::uint8_t kObjectCodeRecord = 9;
constexpr std::uint16_t kAccessReadAll = 0x0007;
constexpr std::uint16_t kAccessWritePreOp = 0x0008;
constexpr std::uint16_t kAccessWriteAll = 0x0038;
constexpr std::uint16_t kAccessRxPdoMappable = 0x0040;
constexpr std::uint16_t kAccessTxPdoMappable = 0x0080;
}  // namespace sdo_info

struct SdoInformationReply {
  std::size_t length{0};             // of the whole mailbox message written, 0: nothing to answer
  std::uint16_t fragments_left{0};   // after this one (0: the answer is complete)
};

// Answers the SDO Information request `coe_payload` (the bytes after the CoE header) with its
// fragment number `fragment` (0 first), written as a whole mailbox message with counter `counter`
// into `response` (at most response.size() bytes: the SM1 length).
SdoInformationReply serve_sdo_information(ConstByteSpan coe_payload, const ObjectDictionary& od, ByteSpan response,
                                          std::uint8_t counter, std::uint16_t fragment) noexcept;

}  // namespace rescue::drivers
