// The CoE SDO server of a simulated drive: one mailbox request in, one mailbox response out, as
// a pure function of (request bytes, object dictionary, EtherCAT state). The caller (the device)
// owns the mailbox counters and the repeat detection; this only answers.
//
//   upload initiate      -> expedited (<= 4 bytes) or normal transfer response, or abort
//   download initiate    -> download response after ObjectDictionary::write, or its abort code
//   segments             -> with a SdoSegmentState (the device's): a value longer than SM1 is
//                           uploaded as a normal transfer announcing its complete size and
//                           carrying what fits, then in upload segments; a normal download that
//                           announces more than it carries is collected from download segments
//                           and written after the last. Toggle errors, segments without a transfer
//                           in progress, or without a state: abort 0x05030000 / 0x05040001
//   complete access      -> the whole object (drivers/sim/coe/coe_complete_access.hpp): upload as a normal
//                           transfer with the CA bit mirrored, download through the single writes
//   abort from the master-> no answer
//   not CoE              -> mailbox error reply "unsupported protocol" (0x0002)
//   SDO information      -> drivers/sim/coe/coe_sdo_information.hpp (OD list, object and entry descriptions)
//   other CoE services   -> mailbox error reply "service not supported" (0x0004) (PDO over mailbox)
//   too short / too long -> mailbox error reply "size too short" (0x0006) / "invalid size" (0x0008)
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"
#include "drivers/sim/coe/object_dictionary.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {

// A segmented transfer in progress (the device's, one per mailbox): what the next segment continues.
struct SdoSegmentState {
  static constexpr std::size_t kCapacity = 256;  // longest value collected from download segments
  bool active{false};
  bool upload{false};
  bool toggle{false};  // the toggle bit the next segment request must carry
  std::uint16_t index{0};
  std::uint8_t subindex{0};
  std::size_t offset{0};  // bytes moved so far
  std::size_t size{0};    // the complete size
  std::array<std::uint8_t, kCapacity> buffer{};  // download: the value collected so far
};

// Writes the response to `request` into `response` (at most response.size() bytes: the SM1
// length) with mailbox counter `counter`; returns its length, 0 when there is nothing to answer.
std::size_t serve_sdo(ConstByteSpan request, ObjectDictionary& od, ecat::reg::AlState state, ByteSpan response,
                      std::uint8_t counter, SdoSegmentState* segments = nullptr) noexcept;

// An answer in several mailbox messages (an SDO Information response longer than SM1): serve_sdo()
// writes the first, this the one numbered `fragment` (1, 2, ...) of the same request; 0 bytes when
// there is no such fragment. The device posts them one after the other, each with its own counter.
std::size_t serve_sdo_fragment(ConstByteSpan request, const ObjectDictionary& od, ByteSpan response,
                               std::uint8_t counter, std::uint16_t fragment) noexcept;

}  // namespace rescue::drivers
