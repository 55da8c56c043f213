// ctl's verbs about the EtherCAT network's slaves (docs/operator.md): `slaves` (each slave's AL state,
// service and recovery, like IgH's `ethercat slaves`), `slaves -v` (each slave's SII identity and AL
// status code, like `ethercat slaves -v`) and `graph` (the topology as the robot sees it now, text,
// dot or JSON, like `ethercat graph`). Each verb's request and printed answer (CtlVerb entries).
#pragma once

#include <cstdint>

#include "core/app/config/command_line.hpp"
#include "core/app/links/protocol_messages.hpp"
#include "core/app/cli/ctl_verbs.hpp"
#include "core/base/result.hpp"

namespace rescue::app {

Result<protocol::Message> build_slaves(const ParsedArgs& args, CtlPeer& peer) noexcept;
int print_slaves_answer(const protocol::Message& request, const protocol::Message& answer) noexcept;
Result<protocol::Message> build_graph(const ParsedArgs& args, CtlPeer& peer) noexcept;
int print_graph_answer(const protocol::Message& request, const protocol::Message& answer) noexcept;

// `diag` and `diag --reset [SLAVE]` (ctl_diag.cpp).
Result<protocol::Message> build_diag(const ParsedArgs& args, CtlPeer& peer) noexcept;
int print_diag_answer(const protocol::Message& request, const protocol::Message& answer) noexcept;

// Names shared by these verbs: an AL state (1 INIT .. 8 OP, "-" unknown) and a slave's service
// ("in exchange", "lost", "out of service", "not in exchange") from its kSlave* flags, and a
// planned slave's name by its position.
const char* al_state_name(std::uint8_t state) noexcept;
const char* slave_service_name(std::uint8_t flags) noexcept;
const char* planned_slave_name(std::size_t position) noexcept;
// The planned slave SLAVE names: a slave's name (ctl slaves: a joint's drive bears its joint's name)
// or its position, decimal 0..22. The number of planned slaves when it names none.
std::size_t planned_slave_named(const char* text) noexcept;

}  // namespace rescue::app
