// SDO complete access (ETG.1000.6 5.6.2, bit 4 of the SDO command): a whole object in one
// transfer, as masters read and write PDO assignment and mapping objects (SOEM's ec_readPDOmapCA
// when the SII announces it). The layout, from the subindex the request names (0 or 1):
//
//   from subindex 0:  SI0 as 16 bits (its UINT8 value, then 0), subindexes 1..n back to back
//   from subindex 1:  subindexes 1..n back to back
//   n = SI0's value (its number of entries); an object without subindexes: just its value
//
// A download writes SI0 = 0 first, then the entries, then SI0 = its new value (CiA 301's order for
// mapping and assignment objects), each write checked as a single one would be (state, access,
// length, the device's check); the first refusal aborts and the object keeps its old content.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"
#include "drivers/sim/coe/object_dictionary.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {

// Whole-object bytes of `index` from `subindex` into `out`; 0 and the length in `length`, or the
// SDO abort code (object or subindex missing, subindex above 1, the object larger than `out`).
std::uint32_t read_complete(const ObjectDictionary& od, std::uint16_t index, std::uint8_t subindex, ByteSpan out,
                            std::size_t& length) noexcept;

// Writes `data` (the layout above) into `index` from `subindex`; 0 or the SDO abort code.
std::uint32_t write_complete(ObjectDictionary& od, std::uint16_t index, std::uint8_t subindex, ConstByteSpan data,
                             ecat::reg::AlState state) noexcept;

}  // namespace rescue::drivers
