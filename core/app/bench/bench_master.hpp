// `rescue-motion bench master`: the EtherCAT master on the simulated robot (in process, virtual
// time; default) or on a raw socket (`--nic raw:IFACE`, e.g. against `rescue-motion sim --iface`
// at the other end of a veth pair). Prints:
//   - time from start to SAFE-OP and to OP, frames used by the bring-up;
//   - DC: max |system time difference| (0x092C) over all slaves after the static drift
//     compensation and after the cyclic run, and from a cold start without static compensation the
//     cycles needed to get under 100 ns and under 20 ns (the simulator's crystals drift up to
//     +-100 ppm); on the simulator also the true offsets from the reference;
//   - SYNC0: spread of the instants the joints latched the same cycle's outputs (simulator only);
//   - the master's own CPU time per cycle (TSC; the NIC's send/receive, i.e. the wire or the
//     simulator, excluded): median, p99, max;
//   - heap allocations and page faults after init (the heap guard counts them; must be 0).
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

int bench_master(const ParsedArgs& args) noexcept;

}  // namespace rescue::app
