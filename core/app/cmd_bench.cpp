// rescue-motion bench NAME: measuring commands. Each prints what it ran on, then `key: value unit`.
#include "core/app/commands.hpp"
#include "core/app/nic_option.hpp"

namespace rescue::app {
namespace {

const OptionSpec kOptions[] = {
    {"nic", "sim|raw:IFACE", "NIC for benchmarks that use the network (default sim)"},
};

int bench_main(const ParsedArgs& args) {
  const Result<NicChoice> nic = parse_nic_option(args.value("nic"));
  if (!nic.ok()) return fail("bench", nic.error().what);
  return fail("bench", "not implemented yet");
}

}  // namespace

const CommandSpec kBenchCommand{
    "bench", "bench NAME [OPTIONS]", "run a measuring command (codec, master, rc, fig4, ...)",
    "Prints the CPU, kernel and privileges it ran with, then one 'key: value unit' line per figure.",
    Span<const OptionSpec>(kOptions), 1, 1, bench_main};

}  // namespace rescue::app
