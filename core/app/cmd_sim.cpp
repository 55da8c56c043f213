// rescue-motion sim: serve the simulated robot's EtherCAT segment on a network interface.
#include "core/app/commands.hpp"

namespace rescue::app {
namespace {

const OptionSpec kOptions[] = {
    {"iface", "IFACE", "network interface to serve the segment on (required)"},
};

int sim_main(const ParsedArgs& /*args*/) { return fail("sim", "not implemented yet"); }

}  // namespace

const CommandSpec kSimCommand{
    "sim", "sim --iface IFACE", "serve the simulated robot's EtherCAT segment on a network interface",
    "A master on the other end of the wire (or of a veth pair) sees the 23 slaves of the robot.",
    Span<const OptionSpec>(kOptions), 0, 0, sim_main};

}  // namespace rescue::app
