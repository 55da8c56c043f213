#include "core/app/cli/ctl_target.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/app/cli/ctl_deadline.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "core/app/config/config_file.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "hal/files/state_dir.hpp"
#include "hal/net/udp_socket.hpp"

namespace rescue::app {
namespace {

// The texts naming what the user gave (one client process: static buffers).
char g_error_text[2048];
char g_key_note[640] = "";  // the key used, and why that one

// The configuration file ctl reads (--config FILE, else the package's when it exists): the robot's
// key_file, control_port and state_dir, so ctl looks where `run --config` does.
constexpr const char* kPackageConfig = "/etc/rescue-motion/rescue-motion.conf";
ConfigFile g_ctl_config;
char g_config_path[kConfigTextCapacity] = "";  // empty: none read

}  // namespace

Status read_ctl_config(const ParsedArgs& args) noexcept {
  const char* path = args.value("config");
  if (path == nullptr) {
    if (::access(kPackageConfig, F_OK) != 0) return Status::success();  // not installed: defaults
    path = kPackageConfig;
  }
  const ConfigOutcome loaded = load_config_file(path, g_ctl_config);
  if (!loaded.ok) {
    char line[384];
    (void)format_config_error(path, loaded.error, line, sizeof line);
    (void)std::snprintf(g_error_text, sizeof g_error_text, "--config %s", line);
    return make_error(Errc::invalid_argument, g_error_text);
  }
  (void)std::snprintf(g_config_path, sizeof g_config_path, "%s", path);
  return Status::success();
}

namespace {

// Where the key is, and why there: --key, the configuration's key_file, or the state directory run
// uses without one (not created here).
struct KeyChoice {
  hal::PathBuffer path;
  char source[kConfigTextCapacity + 64];
};

// `make_dir` (keygen): the state directory is created as run creates it.
Result<KeyChoice> choose_key(const ParsedArgs& args, bool make_dir) noexcept {
  KeyChoice k;
  if (args.value("key") != nullptr) {
    (void)std::snprintf(k.path.text.data(), k.path.text.size(), "%s", args.value("key"));
    (void)std::snprintf(k.source, sizeof k.source, "--key");
    return k;
  }
  if (g_ctl_config.key_file[0] != '\0') {
    (void)std::snprintf(k.path.text.data(), k.path.text.size(), "%s", g_ctl_config.key_file.data());
    (void)std::snprintf(k.source, sizeof k.source, "key_file of %.200s, where run --config reads it", g_config_path);
    return k;
  }
  const char* option = g_ctl_config.state_dir[0] != '\0' ? g_ctl_config.state_dir.data() : nullptr;
  const Result<hal::StateDir> dir =
      make_dir ? hal::resolve_state_dir(option)
               : hal::choose_state_dir(option, hal::system_state_dir_is_default(),
                                       std::getenv("XDG_STATE_HOME"),  // NOLINT(concurrency-mt-unsafe)
                                       std::getenv("HOME"));           // NOLINT(concurrency-mt-unsafe)
  if (!dir.ok()) return make_error(Errc::not_found, "no default key path: no state directory (give --key FILE)");
  const Result<hal::PathBuffer> joined = hal::join_path(dir.value().path.c_str(), "operator.key");
  if (!joined.ok()) return joined.error();
  k.path = joined.value();
  if (option != nullptr) {
    (void)std::snprintf(k.source, sizeof k.source,
                        "the state directory (state_dir of %.200s), where run looks without --key or key_file", g_config_path);
  } else {
    (void)std::snprintf(k.source, sizeof k.source,
                        "the state directory (%s), where run looks without --key or key_file", dir.value().source);
  }
  return k;
}

}  // namespace

Result<CtlTarget> target_of(const ParsedArgs& args) noexcept {
  CtlTarget t;
  const Result<std::uint32_t> address = hal::parse_ipv4(args.value("host") != nullptr ? args.value("host") : "127.0.0.1");
  if (!address.ok()) return make_error(Errc::invalid_argument, "--host must be an IPv4 address");
  t.address = address.value();
  const Result<std::int64_t> port = args.integer("port", 47010, 1, 65535);
  if (!port.ok()) return make_error(Errc::invalid_argument, "--port must be 1..65535");
  t.port = static_cast<std::uint16_t>(port.value());
  const Result<std::int64_t> sender = args.integer("sender", 1, 1, 0xFFFFFFFFLL);
  if (!sender.ok()) return make_error(Errc::invalid_argument, "--sender must be 1..4294967295");
  t.sender = static_cast<std::uint32_t>(sender.value());
  const Result<std::int64_t> robot = args.integer("robot", protocol::kAnyRobot, 0, 999'999'999);
  if (!robot.ok()) return make_error(Errc::invalid_argument, "--robot must be 1..999999999");
  t.robot = static_cast<std::uint32_t>(robot.value());
  const Result<double> timeout = args.number("timeout", 2.0, 0.01, 60.0);
  if (!timeout.ok()) return make_error(Errc::invalid_argument, "--timeout must be 0.01..60 seconds");
  t.timeout_ms = static_cast<int>(timeout.value() * 1000.0);
  if (g_ctl_config.has_control_port && args.value("port") == nullptr) t.port = g_ctl_config.control_port;
  const Result<KeyChoice> choice = choose_key(args, false);
  if (!choice.ok()) return choice.error();
  const hal::PathBuffer& path = choice.value().path;
  hal::FileProblem why;
  const Result<protocol::Key> key = protocol::load_key_file(path.c_str(), why);
  if (!key.ok()) {
    if (key.error().code == Errc::not_found) {
      (void)std::snprintf(g_error_text, sizeof g_error_text,
                          "key file %.255s (%.320s): %.300s; the robot's key is its configuration's key_file (run --config), "
                          "else --key, else <state dir>/operator.key: copy that file here, or make a new one with "
                          "`rescue-motion ctl keygen --key %.255s` and start run with --key %.255s",
                          path.c_str(), choice.value().source, why.c_str(), path.c_str(), path.c_str());
    } else {
      (void)std::snprintf(g_error_text, sizeof g_error_text, "key file refused: %.400s (%.320s); the key file cannot be used",
                          why.c_str(), choice.value().source);
    }
    // A key this station cannot use is local (exit 4) whatever the loader's code: never usage.
    return make_error(key.error().code == Errc::not_found ? Errc::not_found : Errc::permission_denied, g_error_text);
  }
  t.key = key.value();
  (void)std::snprintf(g_key_note, sizeof g_key_note, "key %.255s from %.320s", path.c_str(), choice.value().source);
  return t;
}

Result<CtlTarget> CtlPeer::target() noexcept {
  if (!resolved_) {
    target_ = target_of(args_);
    resolved_ = true;
  }
  return target_;
}

const char* ctl_key_note() noexcept { return g_key_note; }

Result<protocol::Message> CtlPeer::exchange(const protocol::Message& request) noexcept {
  const Result<CtlTarget> to = target();
  if (!to.ok()) return to.error();
  arm_ctl_deadline(static_cast<double>(to.value().timeout_ms) / 1000.0);
  return ctl_exchange(to.value(), request);
}

int ctl_unreachable(const Error& error, const CtlTarget& target) noexcept {
  if (error.code == Errc::refused) {  // another robot id than --robot
    (void)std::snprintf(g_error_text, sizeof g_error_text,
                        "%.32s: unreachable: the robot at that address is robot %u, not robot %u (--robot)",
                        ctl_output().verb, static_cast<unsigned>(error.detail0), static_cast<unsigned>(target.robot));
  } else {
    (void)std::snprintf(g_error_text, sizeof g_error_text, "%.32s: unreachable: %.200s (%.640s)", ctl_output().verb,
                        error.what, g_key_note);
  }
  return ctl_error(CtlExit::unreachable, g_error_text);
}

int ctl_keygen(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  const Result<KeyChoice> choice = choose_key(args, true);
  if (!choice.ok()) return ctl_error(CtlExit::local, choice.error().what);
  const hal::PathBuffer& path = choice.value().path;
  const Status made = protocol::create_key_file(path.c_str());
  if (!made.ok()) {
    (void)std::snprintf(g_error_text, sizeof g_error_text, "keygen %.255s (%.320s): %.100s", path.c_str(), choice.value().source,
                        made.error().what);
    return ctl_error(CtlExit::local, g_error_text);
  }
  if (ctl_output().json) {
    begin_json(true);
    (void)std::printf(R"(,"key_file":)");
    print_json_string(path.c_str());
    (void)std::printf(R"(,"mode":"0600","bytes":32,"source":)");
    print_json_string(choice.value().source);
    end_json();
    return 0;
  }
  (void)std::printf("keygen: wrote a new 32-byte key to %s (mode 0600); copy it to the motion PC and every operator station\n",
                    path.c_str());
  return 0;
}

}  // namespace rescue::app
