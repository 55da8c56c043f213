// Where ctl finds its robot and key (docs/operator.md "Options"): the configuration file (--config,
// else the package's when it exists) for key_file, control_port and state_dir, so ctl looks where
// `run --config` does; the key by --key, key_file, or the state directory; and `ctl keygen`.
#pragma once

#include "core/app/cli/ctl_verbs.hpp"
#include "core/app/config/command_line.hpp"
#include "core/base/result.hpp"

namespace rescue::app {

// Reads the configuration ctl uses (none when not given and not installed).
Status read_ctl_config(const ParsedArgs& args) noexcept;

// The robot to ask: address, port, sender, robot id, timeout, and the key loaded. Errors:
// invalid_argument (an option's value: usage), another code for the key file (local).
Result<CtlTarget> target_of(const ParsedArgs& args) noexcept;

// ctl's error for an exchange that got no fitting answer (`error` from ctl_exchange): "VERB:
// unreachable: ..." naming the key used, or the other robot id. Returns CtlExit::unreachable.
int ctl_unreachable(const Error& error, const CtlTarget& target) noexcept;

// ctl keygen (CtlConverse; asks the robot nothing): a new key file, mode 0600, where the robot looks
// for it. Returns the exit status.
int ctl_keygen(const ParsedArgs& args, CtlPeer& peer) noexcept;

}  // namespace rescue::app
