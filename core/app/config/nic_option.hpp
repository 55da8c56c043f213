// The --nic option shared by `run` and `bench`: which NIC the EtherCAT master talks to.
//   sim         the built-in simulated robot, in process (the default when the option is absent)
//   raw:IFACE   a Linux raw socket on network interface IFACE (hal/net/raw_socket_nic.hpp)
// Parsing only checks the text; whether the interface exists is known when the NIC is opened.
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

}  // namespace rescue::app
