// rescue-motion run: the firmware. Filled in by the master and joint-manager work.
#include "core/app/commands.hpp"
#include "core/app/nic_option.hpp"

namespace rescue::app {
namespace {

const OptionSpec kOptions[] = {
    {"nic", "sim|raw:IFACE", "EtherCAT NIC: the built-in simulated robot (default) or a raw socket"},
    {"scenario", "NAME", "simulator scenario (e.g. link-cut)"},
    {"duration", "SECONDS", "stop after this long (default: run until SIGINT/SIGTERM)"},
    {"capture", "FILE", "record every frame sent and received to a pcapng file"},
    {"state-dir", "DIR", "directory of the error-joints file (default /var/lib/rescue-motion, or per user)"},
};

int run_main(const ParsedArgs& args) {
  const Result<NicChoice> nic = parse_nic_option(args.value("nic"));
  if (!nic.ok()) return fail("run", nic.error().what);
  return fail("run", "not implemented yet");
}

}  // namespace

const CommandSpec kRunCommand{
    "run", "run [OPTIONS]", "run the motion-control firmware (on the simulated robot by default)",
    "SIGINT or SIGTERM stop it cleanly: drives disabled, state saved.",
    Span<const OptionSpec>(kOptions), 0, 0, run_main};

}  // namespace rescue::app
