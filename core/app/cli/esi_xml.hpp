// ctl xml SLAVE (docs/operator.md "ESI from the SII"): an ESI-style description (ETG.2000 element
// names: EtherCATInfo, Vendor, Descriptions, Devices, Device, Sm, RxPdo, TxPdo, Entry, ...) built
// from a slave's SII as the master read it, like IgH's `ethercat xml`. Every string of the SII is
// untrusted: each is XML-escaped (& < > " ' as entities, bytes 0x80-0xFF as character references
// read as Latin-1, other control bytes as U+FFFD). Written into a caller's fixed buffer.
#pragma once

#include <cstddef>

#include "core/base/span.hpp"
#include "ecat/sii/sii.hpp"

namespace rescue::app {

struct EsiSource {
  const char* slave_name{""};     // the network plan's name (in a comment only: not the SII's)
  std::size_t position{0};
  bool strings_skipped{false};    // the master did not read the PDO and entry names (they read "")
};

// Writes the description of `sii` into `out`, NUL-terminated; returns the characters written
// (without the NUL), or 0 when it did not fit.
std::size_t write_esi_xml(const ecat::sii::Sii& sii, const EsiSource& source, Span<char> out) noexcept;

// `text` XML-escaped into `out` (NUL-terminated; cut at a whole character when it does not fit).
// Returns the characters written.
std::size_t xml_escape(const char* text, std::size_t length, Span<char> out) noexcept;

}  // namespace rescue::app
