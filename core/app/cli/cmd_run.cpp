// rescue-motion run: the firmware (core/app/runtime/firmware.hpp).
#include <cstdio>

#include "core/app/cli/commands.hpp"
#include "core/app/runtime/firmware.hpp"
#include "core/app/cli/nic_option.hpp"
#include "core/app/sim/run_scenario.hpp"

namespace rescue::app {
namespace {

const OptionSpec kOptions[] = {
    {"nic", "sim|raw:IFACE", "EtherCAT NIC: the built-in simulated robot (default) or a raw socket"},
    {"scenario", "NAME", "simulated fault scenario: link-cut (cut the cable into l_elbow 1 s after OP)"},
    {"duration", "SECONDS", "stop after this long (default: until SIGINT/SIGTERM, or 1 s after a scenario acted)"},
    {"capture", "FILE", "record every frame sent and received to a pcapng file"},
    {"timing-out", "DIR", "write each real-time task's per-period execution time and wake-up latency there at the end (timing.csv, timing-histogram.txt)"},
    {"state-dir", "DIR", "directory of the error-joints file (default /var/lib/rescue-motion, or per user)"},
    {"initialize", nullptr, "send the operator's 'initialize robot' once the network is in OP (scenarios do)"},
    {"clear-joint", "NAMES", "operator, after a repair: clear these joints (comma-separated) from the error-joints file"},
};

int run_main(const ParsedArgs& args) {
  FirmwareOptions options;
  const Result<NicChoice> nic = parse_nic_option(args.value("nic"));
  if (!nic.ok()) return fail("run", nic.error().what);
  options.nic = nic.value();
  if (args.value("nic") != nullptr) options.nic_text = args.value("nic");
  const Result<Scenario> scenario = parse_scenario(args.value("scenario"));
  if (!scenario.ok()) return fail("run", scenario.error().what);
  options.scenario = scenario.value();
  if (options.scenario.kind != ScenarioKind::none && options.nic.kind != NicKind::sim) {
    return fail("run", "scenarios inject faults into the simulated robot: use --nic sim");
  }
  const Result<double> duration = args.number("duration", 0.0, 0.0, 7.0 * 24 * 3600);
  if (!duration.ok()) return fail("run", "--duration SECONDS", duration.error());
  options.duration = static_cast<hal::Nanoseconds>(duration.value() * static_cast<double>(hal::kNsPerSec));
  options.capture_path = args.value("capture");
  options.timing_out = args.value("timing-out");
  options.state_dir = args.value("state-dir");
  options.initialize = args.has("initialize");
  if (args.value("clear-joint") != nullptr) {
    const Result<JointMask> clear = parse_joint_names(args.value("clear-joint"));
    if (!clear.ok()) {
      char known[kJointNamesCapacity];
      format_joint_names(kAllJoints, known, sizeof known);
      (void)std::fprintf(stderr, "rescue-motion run: --clear-joint '%s': %s (item %u); the joints are: %s\n",
                         args.value("clear-joint"), clear.error().what, static_cast<unsigned>(clear.error().detail0), known);
      return 1;
    }
    options.clear_joints = clear.value();
  }
  return run_firmware(options);
}

}  // namespace

const CommandSpec kRunCommand{
    "run", "run [OPTIONS]", "run the motion-control firmware (on the simulated robot by default)",
    "Reads the error-joints file of the state directory, brings the EtherCAT network up to OP with\n"
    "distributed clocks, and runs the EtherCAT handler (1 ms) and the joint manager. SIGINT or SIGTERM\n"
    "stop it cleanly: drives disabled, state saved. Exit status 0 on a clean stop.\n"
    "After a repair, --clear-joint names the joints to clear: they must answer at bring-up; once they\n"
    "do in OP they leave the error-joints file (logged) and are reset to Idle.",
    Span<const OptionSpec>(kOptions), 0, 0, run_main};

}  // namespace rescue::app
