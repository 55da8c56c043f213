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
    {"duration", "SECONDS", "stop after this long, decimal, above 0, at most 604800 (default: until SIGINT/SIGTERM, or 1 s after a scenario acted)"},
    {"capture", "FILE", "record every frame sent and received to a pcapng file"},
    {"timing-out", "DIR", "write each real-time task's per-period execution time and wake-up latency there at the end (timing.csv, timing-histogram.txt)"},
    {"state-dir", "DIR", "directory of the error-joints file (default /var/lib/rescue-motion, or per user)"},
    {"segment", "NAME", "shared-memory segment of the tasks, \"/NAME\" (default: /rescue-motion-<hash of the state directory>; docs/shared-memory.md)"},
    {"threads", nullptr, "run the tasks as threads of one process (tests, debugging, valgrind) instead of one process each"},
    {"initialize", nullptr, "send the operator's 'initialize robot' once the network is in OP (scenarios do)"},
    {"clear-joint", "NAMES", "operator, after a repair: clear these joints (comma-separated) from the error-joints file"},
    {"listen", "ADDR", "IPv4 address the UDP ports bind (default 0.0.0.0)"},
    {"control-port", "PORT", "operator control UDP port (default 47010)"},
    {"sensor-port", "PORT", "IMU/GPS sensor UDP port (default 47011)"},
    {"key", "FILE", "pre-shared key file (default <state dir>/operator.key; made by: rescue-motion ctl keygen)"},
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
  // 0 is refused rather than read as "forever": leaving --duration out is how to run until a signal.
  if (args.has("duration") && !(duration.value() > 0.0)) {
    return fail("run", "--duration SECONDS: must be above 0 (leave it out to run until SIGINT/SIGTERM)");
  }
  options.duration = static_cast<hal::Nanoseconds>(duration.value() * static_cast<double>(hal::kNsPerSec));
  options.capture_path = args.value("capture");
  options.timing_out = args.value("timing-out");
  options.state_dir = args.value("state-dir");
  options.segment_name = args.value("segment");
  options.initialize = args.has("initialize");
  options.threads = args.has("threads");
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
  const Result<std::int64_t> control_port = args.integer("control-port", 47010, 1, 65535);
  if (!control_port.ok()) return fail("run", "--control-port PORT", control_port.error());
  const Result<std::int64_t> sensor_port = args.integer("sensor-port", 47011, 1, 65535);
  if (!sensor_port.ok()) return fail("run", "--sensor-port PORT", sensor_port.error());
  if (control_port.value() == sensor_port.value()) return fail("run", "--control-port and --sensor-port must differ");
  options.control_port = static_cast<std::uint16_t>(control_port.value());
  options.sensor_port = static_cast<std::uint16_t>(sensor_port.value());
  if (args.value("listen") != nullptr) options.listen = args.value("listen");
  options.key_path = args.value("key");
  return run_firmware(options);
}

}  // namespace

const CommandSpec kRunCommand{
    "run", "run [OPTIONS]", "run the motion-control firmware (on the simulated robot by default)",
    "Reads the error-joints file of the state directory, brings the EtherCAT network up to OP with\n"
    "distributed clocks, and runs the EtherCAT handler (1 ms) and the joint manager. SIGINT or SIGTERM\n"
    "stop it cleanly: drives disabled, state saved. Exit status 0 on a clean stop, 3 when the robot\n"
    "ended in error (every joint in Error), 1 on any other failure.\n"
    "After a repair, --clear-joint names the joints to clear: they must answer at bring-up; once they\n"
    "do in OP they leave the error-joints file (logged) and are reset to Idle.\n"
    "With a key file the operator's commands arrive on the control port and IMU/GPS records on the\n"
    "sensor port (docs/protocol.md); `rescue-motion ctl` is the operator client (docs/operator.md).",
    Span<const OptionSpec>(kOptions), 0, 0, run_main};

}  // namespace rescue::app
