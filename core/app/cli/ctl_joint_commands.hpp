// ctl's commands (ctl_joint_commands.cpp): init, enable, disable, hold, clear [--moved] (the joint
// state machine's verbs), mode, move, hand, and owner [TASK]. Their requests and printed replies.
#pragma once

#include "core/app/cli/ctl_verbs.hpp"
#include "core/app/config/command_line.hpp"
#include "core/app/links/protocol_messages.hpp"
#include "core/base/result.hpp"

namespace rescue::app {

Result<protocol::Message> build_joint_command(const ParsedArgs& args, CtlPeer& peer) noexcept;
Result<protocol::Message> build_mode(const ParsedArgs& args, CtlPeer& peer) noexcept;
Result<protocol::Message> build_move(const ParsedArgs& args, CtlPeer& peer) noexcept;
Result<protocol::Message> build_hand(const ParsedArgs& args, CtlPeer& peer) noexcept;
Result<protocol::Message> build_owner(const ParsedArgs& args, CtlPeer& peer) noexcept;

// A command's reply: accepted (exit 0), or refused with each blocking joint's reason (exit 1).
int print_command_reply(const protocol::Message& request, const protocol::Message& answer) noexcept;
// owner: the owner state (the query) or the reply (owner TASK).
int print_owner_answer(const protocol::Message& request, const protocol::Message& answer) noexcept;

}  // namespace rescue::app
