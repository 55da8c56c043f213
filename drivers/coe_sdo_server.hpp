// The CoE SDO server of a simulated drive: one mailbox request in, one mailbox response out, as
// a pure function of (request bytes, object dictionary, EtherCAT state). The caller (the device)
// owns the mailbox counters and the repeat detection; this only answers.
//
//   upload initiate      -> expedited (<= 4 bytes) or normal transfer response, or abort
//   download initiate    -> download response after ObjectDictionary::write, or its abort code
//   segments             -> abort 0x05040001: no segmented transfer is in progress (every
//                           object of the drive fits one mailbox, so none is ever started)
//   complete access      -> abort 0x06010004 (the SII does not announce it)
//   abort from the master-> no answer
//   not CoE              -> mailbox error reply "unsupported protocol" (0x0002)
//   CoE but not an SDO   -> mailbox error reply "service not supported" (0x0004) (SDO information)
//   too short / too long -> mailbox error reply "size too short" (0x0006) / "invalid size" (0x0008)
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/span.hpp"
#include "drivers/object_dictionary.hpp"
#include "ecat/registers.hpp"

namespace rescue::drivers {

// Writes the response to `request` into `response` (at most response.size() bytes: the SM1
// length) with mailbox counter `counter`; returns its length, 0 when there is nothing to answer.
std::size_t serve_sdo(ConstByteSpan request, ObjectDictionary& od, ecat::reg::AlState state, ByteSpan response,
                      std::uint8_t counter) noexcept;

}  // namespace rescue::drivers
