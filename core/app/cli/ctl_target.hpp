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

// The key used and why that one ("key FILE from SOURCE"), for the message when no answer comes.
const char* ctl_key_note() noexcept;

// ctl keygen: a new key file, mode 0600, where the robot looks for it. Returns the exit status.
int ctl_keygen(const protocol::Message& request, const protocol::Message& answer) noexcept;

// ctl keygen's arguments (CtlBuild; nothing to send).
Result<protocol::Message> build_keygen(const ParsedArgs& args, CtlPeer& peer) noexcept;

}  // namespace rescue::app
