// rescue-motion bench NAME: measuring commands. Each prints what it ran on, then `key: value unit`.
#include <cstdio>
#include <cstring>

#include "core/app/bench/bench_codec.hpp"
#include "core/app/bench/bench_core.hpp"
#include "core/app/bench/bench_fig4.hpp"
#include "core/app/bench/bench_latency.hpp"
#include "core/app/bench/bench_master.hpp"
#include "core/app/bench/bench_nic.hpp"
#include "core/app/bench/bench_periods.hpp"
#include "core/app/bench/bench_rc.hpp"
#include "core/app/bench/bench_sim.hpp"
#include "core/app/bench/bench_wcet.hpp"
#include "core/app/cli/commands.hpp"
#include "core/app/config/nic_option.hpp"

namespace rescue::app {
namespace {

const OptionSpec kOptions[] = {
    {"nic", "sim|raw:IFACE", "NIC for benchmarks that use the network (default sim)"},
    {"ring-nic", "sim|raw:IFACE", "master: cable redundancy, the second master port (another interface than --nic; docs/redundancy.md)"},
    {"ring-cut", "CABLE|none", "master with --nic sim --ring-nic sim: the cable cut a third into the measured run and restored at two thirds (0..22: the cable into that slave position, 23: the ring-return cable; default 9, into l_leg; docs/redundancy.md \"DC method\")"},
    {"frames", "N", "nic: frames to send (default 10000); codec: frames to build and decode (default 200000)"},
    {"cycles", "N", "master: cycles of the measured run (default 10000); sim: cycles of each run (default 60000); periods: measured periods (default 1000)"},
    {"periods", "N", "latency: periods of each loop (default 10000, 10 s each)"},
    {"no-pm-qos", nullptr, "latency: neither loop holds /dev/cpu_dma_latency at 0 (cyclictest --laptop), to measure what the request buys"},
    {"dc-static-frames", "N", "master: at most N static drift compensation frames at bring-up (default 15000)"},
    {"dc-target-ns", "NS", "master: static drift compensation ends once every slave's |0x092C| <= NS twice in a row (default 5; 0 = send every frame)"},
    {"dc-in-flight", "N", "master: static drift compensation frames on their way at a time, 1..8 (default 2; 1 = each waits for the one before)"},
    {"sii-cache-dir", "DIR", "master: keep the SII cache in DIR/sii-cache as `run` keeps it in its state directory (loaded first, saved when bring-up read a new image); default: a cache in memory only"},
    {"cold-start", "yes|no", "master: also measure a bring-up without static drift compensation and, on sim, a bring-up with the SII cache warm (default yes); no: bring-up and the cycles only, as SOEM's test program"},
    {"seed", "S", "master, sim, periods, wcet: seed of the simulated robot's clocks and delays, and of wcet's random gaps (default 1)"},
    {"motion", "hold|move|both", "sim: the joints held, moving, or both runs (default both)"},
    {"scheduling", "rt|normal", "master: rt = the EtherCAT task's SCHED_FIFO 80 on CPU 1 with the master's receive wait (default); normal = default scheduler, any CPU, no spin (as SOEM's test program runs; for comparisons only); wcet: rt = the measuring thread's SCHED_FIFO 80 pinned to a CPU (default); normal = neither (for toolchain/wcet/instructions.sh under callgrind, which is ~50x slower and would hold a CPU at FIFO for minutes)"},
    {"receive-wait", "spin|adaptive|sleep", "master (raw NIC, rt): how the socket waits for the frame: spin up to --receive-spin-us then sleep; adaptive = sleep through the learnt round trip, spin from 20 us before it; sleep = at once (default)"},
    {"receive-spin-us", "US", "master (raw NIC, rt): the receive spin's limit in us (default 150)"},
    {"periods", "N", "rc: timed samples per kernel and RC periods (default 20000); fig4: periods per case (default 5000); wcet: measured periods per task (default 20000, 2500 with --short)"},
    {"load", "LIST", "fig4: background load: stress,udp (default), stress, udp or none"},
    {"out", "DIR", "fig4: directory for fig4.csv, fig4-summary.csv and fig4.png (default /tmp/rescue-fig4); wcet: directory for one samples file per task, pwcet.txt, pwcet.png, capture.pcapng (default /tmp/rescue-wcet)"},
    {"plot-script", "PATH", "fig4: the matplotlib script (default plot_fig4.py beside the program: <prefix>/share/rescue-motion/ when installed, toolchain/ of the source tree for a build)"},
    {"no-plot", nullptr, "fig4: write the CSV files only; wcet: no exceedance plot"},
    {"scenario", "NAME", "wcet: typical, recovery, services, worst (default), worst-ring (worst on the ring configuration) or mixed (docs/timing.md \"Worst-path scenarios\")"},
    {"block", "N", "wcet: periods per block of the block maxima (default 50; make it longer than the scenario's cycle of heavy periods so that each block holds one)"},
    {"short", nullptr, "wcet: the CI form: 2500 periods, 100 bootstrap resamples (checks the method and the refusal, not the bound)"},
};

struct Bench {
  const char* name;
  int (*run)(const ParsedArgs& args) noexcept;
  const char* what;     // bench NAME --help
  const char* options;  // the options it takes, space-separated ("" none)
};

const Bench kBenches[] = {
    {"nic", bench_nic, "round trip of a 60-byte frame through what answers on --nic (e.g. `sim --iface` on a veth pair)",
     "nic frames"},
    {"core", bench_core, "TSC timer, clock, SPSC queue, seqlock, histogram and per-period recording costs; heap and page faults after init", ""},
    {"codec", bench_codec, "build and decode of the robot's cyclic frame (FRMW + 4 LRW), ns per frame and share of its wire time", "frames"},
    {"master", bench_master, "EtherCAT master: time to OP, DC convergence, SYNC0 simultaneity, cycle CPU time, heap after init",
     "nic ring-nic ring-cut cycles dc-static-frames dc-target-ns dc-in-flight seed scheduling sii-cache-dir cold-start receive-wait receive-spin-us"},
    {"sim", bench_sim, "simulated robot speed on virtual time: host ns per 1 ms cycle, simulated seconds per host second",
     "cycles motion seed"},
    {"rc", bench_rc, "RC-task kinematics: FK, Jacobian, DLS of a 7-joint arm, whole-robot FK, task-priority IK step, whole RC period (median/p99/max ns), heap after init", "periods"},
    {"latency", bench_latency, "wake-up latency of the EtherCAT handler's real 1 ms loop (on the in-process simulated robot), of a reference loop interleaved with it (cyclictest's method) and of cyclictest, same priority, CPU and PM QoS; ratios", "periods no-pm-qos"},
    {"periods", bench_periods, "the handler's cycle, the joint manager's step and the RC period on the simulated robot in virtual time", "cycles seed"},
    {"fig4", bench_fig4, "the paper's Fig. 4: EtherCAT handler and RC task at 1 kHz under load, without and with Table I affinity; CSV, PNG, summary",
     "periods load out plot-script no-plot"},
    {"wcet", bench_wcet, "pWCET per real-time task on its worst path (--scenario): per-period times on the simulated robot in virtual time, i.i.d. tests, GEV fit, pWCET at 1e-9 and 1e-12 with their interval or a refusal, plot, the budget against Table I; exit 2 refused, 3 over budget",
     "periods scenario block short seed out no-plot scheduling"},
};

const Bench* find_bench(const char* name) noexcept {
  for (const Bench& bench : kBenches) {
    if (name != nullptr && std::strcmp(bench.name, name) == 0) return &bench;
  }
  return nullptr;
}

// Whether `option` is a word of `list` (space-separated).
bool takes(const Bench& bench, const char* option) noexcept {
  const std::size_t n = std::strlen(option);
  for (const char* at = std::strstr(bench.options, option); at != nullptr; at = std::strstr(at + 1, option)) {
    const bool starts = at == bench.options || at[-1] == ' ';
    const bool ends = at[n] == '\0' || at[n] == ' ';
    if (starts && ends) return true;
  }
  return false;
}

int unknown_bench(const char* name) noexcept {
  (void)std::fprintf(stderr, "rescue-motion bench: unknown benchmark '%s' (known: nic, core, codec, master, sim, rc, latency, periods, fig4, wcet)\n",
                     name != nullptr ? name : "");
  return 2;
}

int bench_main(const ParsedArgs& args) {
  // Each line reaches a pipe when written: the header at once, each figure as it is measured
  // (stdout is block-buffered when piped). Before any output, as setvbuf requires.
  (void)std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const Bench* bench = find_bench(args.positional(0));
  if (bench == nullptr) return unknown_bench(args.positional(0));
  // An option the benchmark does not take is refused, not silently ignored.
  for (const OptionSpec& option : kOptions) {
    if (!args.has(option.name) || takes(*bench, option.name)) continue;
    (void)std::fprintf(stderr, "rescue-motion bench %s: --%s does not apply to %s (it takes: %s; see rescue-motion bench %s --help)\n",
                       bench->name, option.name, bench->name, bench->options[0] != '\0' ? bench->options : "no option",
                       bench->name);
    return 2;
  }
  const Result<NicChoice> nic = parse_nic_option(args.value("nic"));
  if (!nic.ok()) return fail("bench", nic.error().what);
  return bench->run(args);
}

// bench --help: the command's; bench NAME --help: that benchmark's own description and options.
int bench_help(const ParsedArgs& args) {
  if (args.positional_count() == 0) {
    print_command_help(stdout, kBenchCommand);
    return 0;
  }
  const Bench* bench = find_bench(args.positional(0));
  if (bench == nullptr) return unknown_bench(args.positional(0));
  (void)std::printf("usage: rescue-motion bench %s [OPTIONS]\n\n", bench->name);
  print_help_text(stdout, bench->what);
  (void)std::printf("\nOptions:\n");
  bool any = false;
  for (const OptionSpec& option : kOptions) {
    if (!takes(*bench, option.name)) continue;
    // An option described per benchmark ("rc: ...; fig4: ...") is shown only in the rows that name this one.
    char own[24];
    (void)std::snprintf(own, sizeof own, "%s:", bench->name);
    const char* colon = std::strchr(option.help, ':');
    const bool per_bench = colon != nullptr && std::strchr(option.help, ' ') > colon;
    if (per_bench && std::strstr(option.help, own) == nullptr) continue;
    char left[64];
    (void)std::snprintf(left, sizeof left, "--%s%s%s", option.name, option.value_name != nullptr ? " " : "",
                        option.value_name != nullptr ? option.value_name : "");
    print_help_row(stdout, left, option.help);
    any = true;
  }
  if (!any) (void)std::printf("  (none)\n");
  print_help_row(stdout, "-h, --help", "show this help and exit");
  return 0;
}

}  // namespace

const CommandSpec kBenchCommand{
    "bench", "bench NAME [OPTIONS]", "run a measuring command (nic, core, codec, master, sim, rc, latency, periods, fig4, wcet)",
    "Prints the CPU, kernel and privileges it ran with, then one 'key: value unit' line per figure.\n"
    "  nic      round trip of a 60-byte frame through what answers on --nic (`sim --iface` on a veth)\n"
    "  core     TSC timer, clock, SPSC queue, seqlock, histogram and per-period recording costs; heap\n"
    "           and page faults after init\n"
    "  codec    build and decode of the robot's cyclic frame (FRMW + 4 LRW), ns per frame and share of\n"
    "           its wire time\n"
    "  master   EtherCAT master: time to OP, DC convergence, SYNC0 simultaneity, cycle CPU time, heap\n"
    "           after init\n"
    "  sim      simulated robot speed on virtual time: host ns per 1 ms cycle, simulated seconds per\n"
    "           host second\n"
    "  rc       RC-task kinematics: FK, Jacobian, DLS of a 7-joint arm, whole-robot FK, task-priority\n"
    "           IK step, whole RC period (median/p99/max ns), heap after init; KDL ratios:\n"
    "           rescue-bench-rc-kdl\n"
    "  latency  wake-up latency of the handler's 1 ms loop and of cyclictest, same priority and CPU;\n"
    "           ratio\n"
    "  periods  the handler's cycle, the joint manager's step and the RC period on the simulated robot\n"
    "           in virtual time (toolchain/instructions.sh)\n"
    "  fig4     the paper's Fig. 4: EtherCAT handler and RC task at 1 kHz under load, without and with\n"
    "           Table I affinity; CSV, PNG, summary\n"
    "  wcet     pWCET of each real-time task on its worst path (--scenario), its interval or a refusal,\n"
    "           the budget against Table I (toolchain/wcet/pwcet.py)",
    Span<const OptionSpec>(kOptions), 1, 1, bench_main, bench_help};

}  // namespace rescue::app
