// ctl's verbs about the EtherCAT network beyond the plain tables of cmd_ctl.cpp (docs/operator.md):
// `slaves -v` (each slave's SII identity and AL status code, like IgH's `ethercat slaves -v`),
// `graph` (the topology as the robot sees it now, text, dot or JSON, like `ethercat graph`) and
// `diag --reset [SLAVE]` (zero the link error counters). Requests built and answers printed here.
#pragma once

#include <cstdint>

#include "core/app/config/command_line.hpp"
#include "core/app/links/protocol_messages.hpp"
#include "core/base/result.hpp"

namespace rescue::app {

// The request of `verb` if it is one of this file's forms (slaves -v, graph, diag --reset);
// Errc::not_found when it is not (cmd_ctl.cpp builds it), another error for bad arguments.
Result<protocol::Message> build_network_request(const char* verb, const ParsedArgs& args) noexcept;

// Answers: slave_info (slaves -v), graph (--format text or dot, or JSON), and the reply to a
// diag_reset. Each returns ctl's exit status.
int print_slave_info(const protocol::Message& m, bool json) noexcept;
int print_graph(const protocol::Message& m, bool json, const char* format) noexcept;
int print_diag_reset_reply(const protocol::Message& request, const protocol::Message& m, bool json) noexcept;

// Names shared with ctl slaves: an AL state (1 INIT .. 8 OP, "-" unknown) and a slave's service
// ("in exchange", "lost", "out of service", "not in exchange") from its kSlave* flags.
const char* al_state_name(std::uint8_t state) noexcept;
const char* slave_service_name(std::uint8_t flags) noexcept;

}  // namespace rescue::app
