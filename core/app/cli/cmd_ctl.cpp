// rescue-motion ctl: the operator client (sends control messages over UDP).
#include "core/app/cli/commands.hpp"

namespace rescue::app {
namespace {

const OptionSpec kOptions[] = {
    {"host", "ADDR", "address of the motion PC (default 127.0.0.1)"},
    {"port", "PORT", "control UDP port of the motion PC"},
};

int ctl_main(const ParsedArgs& /*args*/) { return fail("ctl", "not implemented yet"); }

}  // namespace

const CommandSpec kCtlCommand{
    "ctl", "ctl [OPTIONS] MESSAGE...", "operator client: send control messages to a running firmware", "",
    Span<const OptionSpec>(kOptions), 0, 8, ctl_main};

}  // namespace rescue::app
