// rescue-motion ctl: the operator client (docs/operator.md). Modelled on IgH's `ethercat` tool and
// ros2_control's CLI: short verbs, readable tables, --json for scripts. This file runs one verb of
// the table (ctl_verbs.hpp): its arguments checked, its request built, exchanged, its answer printed,
// and the exit status of its class (ctl_output.hpp: CtlExit).
#include <algorithm>
#include <cstdio>
#include <cstring>

#include "core/app/cli/commands.hpp"
#include "core/app/cli/ctl_deadline.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "core/app/cli/ctl_target.hpp"
#include "core/app/cli/ctl_verbs.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {
namespace {

using protocol::Message;

const OptionSpec kOptions[] = {
    {"config", "FILE", "the robot's configuration file, for its key_file, control_port and state_dir (default "
                       "/etc/rescue-motion/rescue-motion.conf when it exists)"},
    {"host", "ADDR", "IPv4 address of the motion PC (default 127.0.0.1)"},
    {"port", "PORT", "control UDP port of the motion PC (default: the configuration's control_port, else 47010)"},
    {"key", "FILE", "pre-shared key file (default: the configuration's key_file, else <state dir>/operator.key, "
                    "where run looks without one)"},
    {"sender", "ID", "this operator's sender id, 1..4294967295 (default 1); one per operator station"},
    {"robot", "ID", "the robot id expected (run's --robot-id); another robot at the address is refused (default: any)"},
    {"task", "N", "RC task for move, hand (default 0)"},
    {"json", nullptr, "print the answer as one JSON object"},
    {"moved", nullptr, "clear: also confirm joints that returned away from their held position"},
    {"timeout", "SECONDS", "how long to wait for the robot's answer (default 2; keygen 10)"},
    {"count", "N", "watch: refresh this many times, then exit (default: until interrupted)"},
    {"interval", "SECONDS", "watch: refresh period (default 0.5)"},
    {"type", "TYPE", "upload, download: the value's type: u8, u16, u32, i8, i16, i32, string or hex "
                     "(default: by the object's size)"},
    {"verbose", nullptr, "slaves: each slave's identity (SII: vendor, product, revision, serial) and AL status code", 'v'},
    {"format", "FORMAT", "graph: text (default) or dot (Graphviz)"},
    {"reset", nullptr, "diag: zero the link error counters (all slaves, or SLAVE)"},
    {"raw", nullptr, "sii_read: the image's bytes themselves on stdout (not a hex dump)"},
    {"values", nullptr, "sdos: each entry's value too (SDO upload)"},
};

char g_error_text[1024];  // the text naming what went wrong (one client process)

// The arguments of `verb`: as many as its entry takes, and only the options that go with it.
int check_arguments(const CtlVerb& verb, const ParsedArgs& args) noexcept {
  const std::size_t n = args.positional_count() - 1;
  if (n < verb.min_args || n > verb.max_args) {
    (void)std::snprintf(g_error_text, sizeof g_error_text, "%s: %s arguments; usage: ctl %s", verb.name,
                        n < verb.min_args ? "missing" : "too many", verb.usage);
    return ctl_error(CtlExit::usage, g_error_text);
  }
  for (const CtlVerbOption& o : kCtlVerbOptions) {
    const bool belongs = std::any_of(std::begin(o.verbs), std::end(o.verbs),
                                     [&verb](const char* v) { return v != nullptr && std::strcmp(v, verb.name) == 0; });
    if (args.has(o.option) && !belongs) return ctl_error(CtlExit::usage, o.error);
  }
  return 0;
}

// One exchange and its printed answer.
int exchange_and_print(const CtlVerb& verb, const CtlTarget& target, const Message& request) noexcept {
  const Result<Message> answer = ctl_exchange(target, request);
  if (!answer.ok()) return ctl_unreachable(answer.error(), target);
  return verb.print(request, answer.value());
}

// watch: the exchange again every --interval, --count times (0: until interrupted).
int repeat(const CtlVerb& verb, const ParsedArgs& args, const CtlTarget& target, const Message& request) noexcept {
  disarm_ctl_deadline();  // watch runs until --count: each exchange keeps its own deadline
  const Result<std::int64_t> count = args.integer("count", 0, 0, 1'000'000'000);
  if (!count.ok()) return ctl_error(CtlExit::usage, "watch: --count must be 0..1000000000 (0: until interrupted)");
  const Result<double> interval = args.number("interval", 0.5, 0.05, 3600.0);
  if (!interval.ok()) return ctl_error(CtlExit::usage, "watch: --interval must be 0.05..3600 seconds");
  hal::MonotonicClock clock;
  hal::Nanoseconds next = clock.now();
  for (std::int64_t i = 0; count.value() == 0 || i < count.value(); ++i) {
    if (!ctl_output().json) (void)std::printf("\033[H\033[2J");  // refreshed in place
    const int status = exchange_and_print(verb, target, request);
    (void)std::fflush(stdout);
    if (status != 0) return status;
    next += static_cast<hal::Nanoseconds>(interval.value() * 1e9);
    clock.sleep_until(next);
  }
  return 0;
}

int ctl_main(const ParsedArgs& args) {
  const char* name = args.positional(0);
  CtlOutput& out = ctl_output();
  out.json = args.has("json");
  out.format = args.value("format");
  out.verb = name != nullptr ? name : "ctl";
  const CtlVerb* verb = name != nullptr ? find_ctl_verb(name) : nullptr;
  if (verb == nullptr) return ctl_error(CtlExit::usage, "unknown verb (see rescue-motion ctl --help)");
  const int wrong = check_arguments(*verb, args);
  if (wrong != 0) return wrong;
  // keygen waits for no robot, only for its key to reach the disk (fsync): on a busy laptop that
  // alone can take seconds, so its default allowance is longer; --timeout still bounds it.
  const double default_deadline = std::strcmp(verb->name, "keygen") == 0 ? kKeygenDefaultTimeoutSeconds : 2.0;
  const Result<double> deadline = args.number("timeout", default_deadline, 0.01, 60.0);
  if (!deadline.ok()) return ctl_error(CtlExit::usage, "--timeout must be 0.01..60 seconds");
  arm_ctl_deadline(deadline.value());
  if (!protocol::init_crypto().ok()) return ctl_error(CtlExit::local, "libsodium could not be initialised");
  const Status config = read_ctl_config(args);
  if (!config.ok()) return ctl_error(CtlExit::local, config.error().what);
  CtlPeer peer(args);
  if (verb->run == CtlRun::own) return verb->converse(args, peer);
  const Result<Message> request = verb->build(args, peer);
  if (!request.ok()) return ctl_error(exit_of(request.error().code), request.error().what);
  const Result<CtlTarget> target = peer.target();
  if (!target.ok()) return ctl_error(exit_of(target.error().code), target.error().what);
  if (verb->run == CtlRun::repeated) return repeat(*verb, args, target.value(), request.value());
  return exchange_and_print(*verb, target.value(), request.value());
}

}  // namespace

const CommandSpec kCtlCommand{
    "ctl", "ctl [OPTIONS] VERB [ARGS]", "operator client: query and command a running firmware (docs/operator.md)",
    "Verbs:\n"
    "  status | slaves | master | tasks     the robot's joints, EtherCAT slaves, master counters, tasks\n"
    "  slaves -v                            per slave: SII vendor, product, revision, serial; AL status code\n"
    "  diag                                 link-quality counters per slave and port, warnings naming the cable\n"
    "  diag --reset [SLAVE]                 zero the link error counters (all slaves, or SLAVE: name or position)\n"
    "  graph [--format dot]                 the topology now: chains on junction ports, joints behind each cable\n"
    "  watch                                status, refreshed in place (--interval, --count)\n"
    "  init [JOINTS]                        'initialize robot': mode, reference := position, enable\n"
    "  enable [JOINTS] | disable [JOINTS]   DFA enable / disable (JOINTS: comma-separated names or all)\n"
    "  hold [JOINTS]                        Enabled joints stop and hold where they stand\n"
    "  mode JOINT MODE                      select csp, csv or cst\n"
    "  clear JOINTS [--moved]               clear joints after repair (error-joints file), then reset;\n"
    "                                       --moved: also confirm joints back away from their held position\n"
    "  move EFFECTOR POSE                   left|right x,y,z,roll,pitch,yaw to RC task --task\n"
    "  hand left|right open|close           to RC task --task\n"
    "  owner TASK                           RC task TASK takes the motion\n"
    "  owner                                which RC task owns the motion, each task alive or not, its phase\n"
    "  version                              the robot's program version, layout and build type, and ctl's own\n"
    "  upload SLAVE INDEX:SUB               read a CoE object (SDO; e.g. 0x100A:00), --type; SLAVE: a joint,\n"
    "                                       a slave's name or position (junctions too; e.g. upload 1 0x1018:01)\n"
    "  download SLAVE INDEX:SUB VALUE       write one; objects of the cyclic image are refused with the reason\n"
    "  pdos [SLAVE]                         the sync managers, PDO assignment and mapping the master\n"
    "                                       configures; with SLAVE (joint, name or position) also read\n"
    "                                       back from its drive (SDO), each same or not\n"
    "  sdos SLAVE [--values]                the slave's object dictionary as it describes it (CoE SDO\n"
    "                                       Information): objects, entries, types, access; --values\n"
    "                                       each entry's value too (SDO upload)\n"
    "  sii_read SLAVE [--raw]               the slave's SII as the master read it at bring-up: hex dump,\n"
    "                                       or the bytes themselves (--raw)\n"
    "  xml SLAVE                            an ESI-style XML description built from that SII (vendor,\n"
    "                                       product, names, sync managers, PDOs), like `ethercat xml`\n"
    "  reg_read SLAVE ADDR [LEN]            read LEN bytes (1..64, default 1) of the slave's ESC registers\n"
    "                                       from ADDR (e.g. 0x0130 AL status), read only; no reg_write\n"
    "  states [SLAVES] STATE                AL state INIT, PREOP, SAFEOP or OP for slaves out of service\n"
    "                                       (refused for a slave in service), as `ethercat states`\n"
    "  rescan                               identify every device again (SII, in the cyclic frames) and\n"
    "                                       list what differs from the plan (missing, extra, moved, ...)\n"
    "  keygen                               create a new key file (--key FILE), mode 0600\n"
    "Exit status: 0 the robot accepted the command or answered the query; 1 refused (by the robot or\n"
    "the drive, with the reason); 2 usage (a bad verb, option or argument); 3 unreachable (no authentic\n"
    "answer in time, or another robot id); 4 local (the key or configuration file unusable); 5 an\n"
    "answer that does not fit the request.",
    Span<const OptionSpec>(kOptions), 1, 4, ctl_main};

}  // namespace rescue::app
