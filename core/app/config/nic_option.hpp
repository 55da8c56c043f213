// The --nic option shared by `run` and `bench`: which NIC the EtherCAT master talks to.
//   sim         the built-in simulated robot, in process (the default when the option is absent)
//   raw:IFACE   a Linux raw socket on network interface IFACE (hal/net/raw_socket_nic.hpp)
// Parsing only checks the text; whether the interface exists is known when the NIC is opened.
// --ring-nic (cable redundancy, docs/redundancy.md): the second master port, cabled to the segment's
// far end: raw:IFACE beside --nic raw:IFACE (another interface), or sim beside --nic sim.
#pragma once

#include <array>
#include <cstdint>

#include "core/base/result.hpp"
#include "hal/net/raw_socket_nic.hpp"

namespace rescue::app {

enum class NicKind : std::uint8_t { sim, raw };

struct NicChoice {
  NicKind kind{NicKind::sim};
  std::array<char, hal::kMaxInterfaceNameLength + 1> interface_name{};  // raw only, zero-terminated
};

// `text` is the option's value, nullptr when absent (-> sim). Errors are invalid_argument with a
// message fit for the command line.
Result<NicChoice> parse_nic_option(const char* text) noexcept;

// `text` is --ring-nic's value (not null), `main` the --nic choice. Refused with the reason: the
// main interface itself (a ring needs a second port), a raw ring beside the simulated robot or the
// other way round.
Result<NicChoice> parse_ring_nic_option(const char* text, const NicChoice& main) noexcept;

}  // namespace rescue::app
