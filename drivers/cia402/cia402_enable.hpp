// The master's side of CiA 402 (drivers/cia402/cia402.hpp is the drive's side): which controlword takes a
// drive, one step per cycle, from the state its statusword shows to Operation enabled, or back to
// a safe stop. Used by whoever writes the joints' outputs (the EtherCAT handler for "enable" and
// "disable" joint messages, tests and benchmarks).
//
//   Switch on disabled  -> shutdown (0x0006)          Ready to switch on -> switch on (0x0007)
//   Switched on         -> enable operation (0x000F)  Operation enabled  -> enable operation (hold)
//   Fault               -> fault reset: 0x0080, after a cycle with bit 7 clear (the reset is the
//                          rising edge of bit 7)
//   Quick stop active, fault reaction active, not ready -> disable voltage (0x0000) and wait
#pragma once

#include <cstdint>

namespace rescue::drivers {

// Next controlword towards Operation enabled. `previous` is the controlword sent last cycle.
std::uint16_t controlword_towards_enabled(std::uint16_t statusword, std::uint16_t previous) noexcept;

// Next controlword towards a stop with the power stage off (Switch on disabled): disable voltage,
// except in Operation enabled where "disable operation" first lets the drive stop on its ramp.
std::uint16_t controlword_towards_disabled(std::uint16_t statusword) noexcept;

bool is_enabled(std::uint16_t statusword) noexcept;
bool is_faulted(std::uint16_t statusword) noexcept;

}  // namespace rescue::drivers
