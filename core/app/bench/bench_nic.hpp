// `rescue-motion bench nic --nic raw:IFACE [--frames N]`: round trip of one small EtherCAT frame
// (a 2-byte BRD, 60 bytes on the wire) through whatever answers on the NIC: the simulator served by
// `rescue-motion sim --iface` on the other end of a veth pair, or a real slave chain. One frame in
// flight at a time, as in the 1 ms cycle; min, median, 99th percentile and max.
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

int bench_nic(const ParsedArgs& args) noexcept;

}  // namespace rescue::app
