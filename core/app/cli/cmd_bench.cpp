// rescue-motion bench NAME: measuring commands. Each prints what it ran on, then `key: value unit`.
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
#include "core/app/cli/commands.hpp"
#include "core/app/config/nic_option.hpp"

namespace rescue::app {
namespace {

const OptionSpec kOptions[] = {
    {"nic", "sim|raw:IFACE", "NIC for benchmarks that use the network (default sim)"},
    {"frames", "N", "nic: frames to send (default 10000); codec: frames to build and decode (default 200000)"},
    {"cycles", "N", "master: cycles of the measured run (default 10000); sim: cycles of each run (default 60000); periods: measured periods (default 1000)"},
    {"periods", "N", "latency: periods of each loop (default 10000, 10 s each)"},
    {"dc-static-frames", "N", "master: at most N static drift compensation frames at bring-up (default 15000)"},
    {"dc-target-ns", "NS", "master: static drift compensation ends once every slave's |0x092C| <= NS twice in a row (default 5; 0 = send every frame)"},
    {"seed", "S", "master, sim, periods: seed of the simulated robot's clocks and delays (default 1)"},
    {"motion", "hold|move|both", "sim: the joints held, moving, or both runs (default both)"},
    {"scheduling", "rt|normal", "master: rt = the EtherCAT task's SCHED_FIFO 80 on CPU 1 with the 150 us receive spin (default); normal = default scheduler, any CPU, no spin (as SOEM's test program runs; for comparisons only)"},
    {"periods", "N", "rc: timed samples per kernel and RC periods (default 20000); fig4: periods per case (default 5000)"},
    {"load", "LIST", "fig4: background load: stress,udp (default), stress, udp or none"},
    {"out", "DIR", "fig4: directory for fig4.csv, fig4-summary.csv and fig4.png (default /tmp/rescue-fig4)"},
    {"plot-script", "PATH", "fig4: the matplotlib script (default toolchain/plot_fig4.py, from the source tree)"},
    {"no-plot", nullptr, "fig4: write the CSV files only"},
};

struct Bench {
  const char* name;
  int (*run)(const ParsedArgs& args) noexcept;
};

const Bench kBenches[] = {
    {"nic", bench_nic},
    {"core", bench_core},
    {"codec", bench_codec},
    {"master", bench_master},
    {"sim", bench_sim},
    {"rc", bench_rc},
    {"latency", bench_latency},
    {"periods", bench_periods},
    {"fig4", bench_fig4},
};

int bench_main(const ParsedArgs& args) {
  const Result<NicChoice> nic = parse_nic_option(args.value("nic"));
  if (!nic.ok()) return fail("bench", nic.error().what);
  for (const Bench& bench : kBenches) {
    if (std::strcmp(bench.name, args.positional(0)) == 0) return bench.run(args);
  }
  return fail("bench", "unknown benchmark (see rescue-motion bench --help)");
}

}  // namespace

const CommandSpec kBenchCommand{
    "bench", "bench NAME [OPTIONS]", "run a measuring command (nic, core, codec, master, sim, rc, latency, periods, fig4)",
    "Prints the CPU, kernel and privileges it ran with, then one 'key: value unit' line per figure.\n"
    "  nic    round trip of a 60-byte frame through what answers on --nic (e.g. `sim --iface` on a veth pair)\n"
    "  core   TSC timer, clock, SPSC queue, seqlock, histogram and per-period recording costs; heap and page faults after init\n"
    "  codec  build and decode of the robot's cyclic frame (FRMW + 4 LRW), ns per frame and share of its wire time\n"
    "  master EtherCAT master: time to OP, DC convergence, SYNC0 simultaneity, cycle CPU time, heap after init\n"
    "  sim    simulated robot speed on virtual time: host ns per 1 ms cycle, simulated seconds per host second\n"
    "  rc     RC-task kinematics: FK, Jacobian, DLS of a 7-joint arm, whole-robot FK, task-priority IK step,\n"
    "         whole RC period (median/p99/max ns), heap after init; KDL ratios: rescue-bench-rc-kdl\n"
    "  latency wake-up latency of the handler's 1 ms loop and of cyclictest, same priority and CPU; ratio\n"
    "  periods the handler's cycle, the joint manager's step and the RC period on the simulated robot in virtual time (toolchain/instructions.sh)\n"
    "  fig4   the paper's Fig. 4: EtherCAT handler and RC task at 1 kHz under load, without and with Table I affinity; CSV, PNG, summary",
    Span<const OptionSpec>(kOptions), 1, 1, bench_main};

}  // namespace rescue::app
