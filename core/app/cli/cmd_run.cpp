// rescue-motion run: the firmware (core/app/runtime/firmware.hpp).
#include <cstdio>
#include <cstring>

#include "core/app/cli/commands.hpp"
#include "core/app/config/config_file.hpp"
#include "core/app/config/firmware_config.hpp"
#include "core/app/config/nic_option.hpp"
#include "core/app/config/task_table.hpp"
#include "core/app/links/protocol_messages.hpp"
#include "core/app/runtime/firmware.hpp"
#include "core/app/runtime/self_check.hpp"
#include "core/app/runtime/stop_signal.hpp"
#include "core/app/sim/run_scenario.hpp"
#include "hal/rt/privileges.hpp"

namespace rescue::app {
namespace {

const OptionSpec kOptions[] = {
    {"config", "FILE", "configuration file (docs/configuration.md; /etc/rescue-motion/rescue-motion.conf in the package); options given here override it"},
    {"check", nullptr, "self-test and exit: bring the network to OP and back to INIT with every drive disabled; exit 0/1, one line (and the bring-up report when bring-up fails); takes only --config, --nic, --ring-nic and --capture"},
    {"nic", "sim|raw:IFACE", "EtherCAT NIC: the built-in simulated robot (default) or a raw socket"},
    {"ring-nic", "sim|raw:IFACE", "cable redundancy: the second master port, cabled to the segment's far end (another interface than --nic; docs/redundancy.md); a ring that does not close refuses the bring-up"},
    {"scenario", "NAME", "simulated scenario: link-cut (cut the cable into l_elbow 1 s after OP), rescue (the rescue motion, owned by RC task 0, with that cut mid-motion), power-cycle (power-cycle l_elbow's drive 1 s after OP), half-mapped / foreign-mapping (l_elbow's PDO mapping half-written / another drive's default before bring-up and again before a power cycle 1 s after OP: the master rewrites it both times), cable-damage (5 frames damaged on the cable into l_elbow 1 s after OP), flaky-cable (that damage again every 2 s)"},
    {"duration", "SECONDS", "stop after this long, decimal, at least 0.001 (one period), at most 604800 (default: until SIGINT/SIGTERM, or 1 s after a scenario acted)"},
    {"first-contact-limit", "SECONDS", "give the bring-up up (exit status 1) when no frame has come back for this long, decimal, at most 604800; 0: keep trying until SIGINT/SIGTERM (default 5); meanwhile the wait is reported every second"},
    {"capture", "FILE", "record every frame sent and received to a pcapng file"},
    {"timing-out", "DIR", "write each real-time task's per-period execution time and wake-up latency there at the end (timing.csv, timing-histogram.txt)"},
    {"state-dir", "DIR", "directory of the error-joints file (default /var/lib/rescue-motion, or per user)"},
    {"segment", "NAME", "shared-memory segment of the tasks, \"/NAME\" (default: /rescue-motion-<hash of the state directory>; docs/shared-memory.md)"},
    {"threads", nullptr, "run the tasks as threads of one process (tests, debugging, valgrind) instead of one process each"},
    {"initialize", nullptr, "send the operator's 'initialize robot' once the network is in OP (scenarios do)"},
    {"auto-clear-power-cycled", nullptr, "a joint whose drive was power-cycled and brought back online returns to Idle without the operator's clear (unless it moved)"},
    {"clear-joint", "NAMES", "operator, after a repair: clear these joints (comma-separated) from the error-joints file"},
    {"listen", "ADDR", "IPv4 address the UDP ports bind (default 0.0.0.0)"},
    {"control-port", "PORT", "operator control UDP port (default 47010)"},
    {"sensor-port", "PORT", "IMU/GPS sensor UDP port (default 47011)"},
    {"key", "FILE", "pre-shared key file (default <state dir>/operator.key; made by: rescue-motion ctl keygen)"},
    {"robot-id", "N", "this robot's identity in every datagram, 1..999999999 (default 1; give each robot its own)"},
};

// The configuration file, when --config names one (static: its texts outlive the run).
ConfigFile g_config;

// A text of the file, or nullptr when it did not set it.
const char* from_file(const ConfigText& text) noexcept { return text[0] != '\0' ? text.data() : nullptr; }
// The command line's value, else the file's, else nullptr.
const char* option_or_file(const ParsedArgs& args, const char* name, const ConfigText& text) noexcept {
  return args.value(name) != nullptr ? args.value(name) : from_file(text);
}

// Says which capabilities and limits are missing and what that costs (docs/deploy.md).
void report_privileges(const NicChoice& nic) noexcept {
  const Result<hal::Privileges> have = hal::query_privileges();
  if (!have.ok()) {
    (void)std::printf("rescue-motion run: privileges unknown: %s (errno %u)\n", have.error().what, have.error().detail0);
    return;
  }
  hal::PrivilegeNeeds needs;
  for (const TaskSpec& t : task_table()) {
    const int priority = runner_priority(t.id);
    if (priority > needs.max_priority) needs.max_priority = priority;
  }
  needs.raw_socket = nic.kind == NicKind::raw;
  (void)hal::describe_privileges(have.value(), needs, "rescue-motion run: privileges: ", stdout);
}

int run_main(const ParsedArgs& args) {
  // --check: each line reaches a pipe when written (stdout is block-buffered when piped); set before
  // the first output, as setvbuf requires.
  if (args.has("check")) (void)std::setvbuf(stdout, nullptr, _IOLBF, 0);
  FirmwareOptions options;
  if (args.value("config") != nullptr) {
    const ConfigOutcome loaded = load_config_file(args.value("config"), g_config);
    if (!loaded.ok) {
      char line[1024];
      (void)format_config_error(args.value("config"), loaded.error, line, sizeof line);
      (void)std::fprintf(stderr, "rescue-motion run: --config %s\n", line);
      return 1;
    }
    apply_task_placements(g_config);
  }
  const char* nic_text = option_or_file(args, "nic", g_config.nic_text);
  const Result<NicChoice> nic = parse_nic_option(nic_text);
  if (!nic.ok()) return fail("run", nic.error().what);
  options.nic = nic.value();
  if (nic_text != nullptr) options.nic_text = nic_text;
  const char* ring_nic_text = option_or_file(args, "ring-nic", g_config.ring_nic_text);
  if (ring_nic_text != nullptr) {
    const Result<NicChoice> ring = parse_ring_nic_option(ring_nic_text, options.nic);
    if (!ring.ok()) return fail("run", ring.error().what);
    options.ring_nic = ring.value();
    options.ring_nic_text = ring_nic_text;
  }
  if (args.has("check")) {
    // --check takes the NIC (and --config, --capture); the options of a running robot mean nothing to
    // it and are refused by name rather than silently dropped.
    for (const OptionSpec& o : kOptions) {
      const bool applies = std::strcmp(o.name, "check") == 0 || std::strcmp(o.name, "config") == 0 ||
                           std::strcmp(o.name, "nic") == 0 || std::strcmp(o.name, "ring-nic") == 0 ||
                           std::strcmp(o.name, "capture") == 0;
      if (!applies && args.has(o.name)) {
        (void)std::fprintf(stderr, "rescue-motion run: --%s does not apply to --check (it takes --config, --nic, --ring-nic and --capture)\n", o.name);
        return 1;
      }
    }
    if (!install_stop_handlers()) return fail("run", "cannot install SIGINT/SIGTERM handlers");
    SelfCheckOptions check;
    check.nic = options.nic;
    check.nic_text = options.nic_text;
    check.ring_nic = options.ring_nic;
    check.ring_nic_text = options.ring_nic_text;
    check.capture_path = args.value("capture");
    check.progress = stderr;
    return run_self_check(check, stdout, nullptr);
  }
  report_privileges(options.nic);
  const Result<Scenario> scenario = parse_scenario(args.value("scenario"));
  if (!scenario.ok()) return fail("run", scenario.error().what);
  options.scenario = scenario.value();
  if (options.scenario.kind != ScenarioKind::none && options.nic.kind != NicKind::sim) {
    return fail("run", "scenarios inject faults into the simulated robot: use --nic sim");
  }
  const Result<double> duration = args.number("duration", g_config.duration_s, 0.0, 7.0 * 24 * 3600);
  if (!duration.ok()) return fail("run", "--duration SECONDS", duration.error());
  // 0 is refused rather than read as "forever": leaving --duration out is how to run until a signal.
  if ((args.has("duration") || g_config.has_duration) && !(duration.value() > 0.0)) {
    return fail("run", "--duration SECONDS: must be above 0 (leave it out to run until SIGINT/SIGTERM)");
  }
  options.duration = static_cast<hal::Nanoseconds>(duration.value() * static_cast<double>(hal::kNsPerSec));
  // Below one period no cycle would run (and a duration that rounds to 0 ns would mean "forever").
  if ((args.has("duration") || g_config.has_duration) && options.duration < config::kEthercatHandlerPeriodNs) {
    return fail("run", "--duration SECONDS: must be at least one period of the EtherCAT handler (0.001 s)");
  }
  const Result<double> first_contact = args.number("first-contact-limit", 5.0, 0.0, 7.0 * 24 * 3600);
  if (!first_contact.ok()) return fail("run", "--first-contact-limit SECONDS", first_contact.error());
  options.first_contact_limit = static_cast<hal::Nanoseconds>(first_contact.value() * static_cast<double>(hal::kNsPerSec));
  options.capture_path = args.value("capture");
  options.timing_out = args.value("timing-out");
  // The configuration file's rule for its path values, on the command line too (one rule for both).
  for (const char* path_option : {"state-dir", "key"}) {
    const char* given = args.value(path_option);
    const char* problem = given != nullptr ? path_value_problem(given) : nullptr;
    if (problem != nullptr) {
      (void)std::fprintf(stderr, "rescue-motion run: --%s %s: %s (%s, as in the configuration file)\n", path_option, given,
                         problem, kPathValueRule);
      return 1;
    }
  }
  options.state_dir = option_or_file(args, "state-dir", g_config.state_dir);
  options.segment_name = args.value("segment");
  options.initialize = args.has("initialize");
  options.threads = args.has("threads");
  options.auto_clear_power_cycled = args.has("auto-clear-power-cycled") || g_config.auto_clear_power_cycled;
  if (g_config.task_silent_ms != 0) options.task_silent_after = static_cast<hal::Nanoseconds>(g_config.task_silent_ms) * hal::kNsPerMs;
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
  const Result<std::int64_t> control_port =
      args.integer("control-port", g_config.has_control_port ? g_config.control_port : 47010, 1, 65535);
  if (!control_port.ok()) return fail("run", "--control-port PORT", control_port.error());
  const Result<std::int64_t> sensor_port =
      args.integer("sensor-port", g_config.has_sensor_port ? g_config.sensor_port : 47011, 1, 65535);
  if (!sensor_port.ok()) return fail("run", "--sensor-port PORT", sensor_port.error());
  if (control_port.value() == sensor_port.value()) return fail("run", "--control-port and --sensor-port must differ");
  options.control_port = static_cast<std::uint16_t>(control_port.value());
  options.sensor_port = static_cast<std::uint16_t>(sensor_port.value());
  const Result<std::int64_t> robot_id =
      args.integer("robot-id", g_config.has_robot_id ? g_config.robot_id : protocol::kDefaultRobotId, 1, 999'999'999);
  if (!robot_id.ok()) return fail("run", "--robot-id N (1..999999999)", robot_id.error());
  options.robot_id = static_cast<std::uint32_t>(robot_id.value());
  if (option_or_file(args, "listen", g_config.listen) != nullptr) options.listen = option_or_file(args, "listen", g_config.listen);
  options.key_path = option_or_file(args, "key", g_config.key_file);
  return run_firmware(options);
}

}  // namespace

const CommandSpec kRunCommand{
    "run", "run [OPTIONS]", "run the motion-control firmware (on the simulated robot by default)",
    "Reads the error-joints file of the state directory, brings the EtherCAT network up to OP with\n"
    "distributed clocks, and runs the EtherCAT handler (1 ms) and the joint manager. SIGINT or SIGTERM\n"
    "stop it cleanly: drives disabled, state saved. Exit status 0 on a clean stop, 3 when the robot\n"
    "ended in error (every joint in Error), 1 on any other failure (4, 5, 6: the man page's EXIT STATUS).\n"
    "After a repair, --clear-joint names the joints to clear: they must answer at bring-up; once they\n"
    "do in OP they leave the error-joints file (logged) and are reset to Idle.\n"
    "With a key file the operator's commands arrive on the control port and IMU/GPS records on the\n"
    "sensor port (docs/protocol.md); `rescue-motion ctl` is the operator client (docs/operator.md).\n"
    "--config FILE reads these settings and each task's priority and CPU from a file\n"
    "(docs/configuration.md); an option on the command line overrides the file. At start the run says\n"
    "which of CAP_NET_RAW, CAP_SYS_NICE, CAP_IPC_LOCK, RLIMIT_RTPRIO and RLIMIT_MEMLOCK it lacks and\n"
    "what that costs.\n"
    "--check brings the network to OP and back to INIT without enabling a drive, prints one line and\n"
    "exits 0 (OK) or 1 (docs/deploy.md); a line per phase goes to standard error as it starts.",
    Span<const OptionSpec>(kOptions), 0, 0, run_main};

}  // namespace rescue::app
