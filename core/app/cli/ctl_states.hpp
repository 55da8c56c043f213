// ctl states [SLAVES] STATE (docs/operator.md "AL states"): an AL state (INIT, PREOP, SAFEOP, OP)
// for slaves that are out of service, like IgH's `ethercat states`; SLAVES a comma-separated list of
// slaves' names or positions (ctl slaves), or all (the default). The robot's master writes AL
// control in its cyclic frames and answers when every slave reached the state, or with each one's
// AL status and code when one did not (exit 1); a slave whose joints are in service is refused with
// them named (exit 1), nothing written.
#pragma once

#include "core/app/cli/ctl_verbs.hpp"
#include "core/app/config/command_line.hpp"

namespace rescue::app {

Result<protocol::Message> build_states(const ParsedArgs& args, CtlPeer& peer) noexcept;
int print_states_result(const protocol::Message& request, const protocol::Message& answer) noexcept;

}  // namespace rescue::app
