// The operator client's exchange (rescue-motion ctl, docs/operator.md): one authenticated request to
// the robot's control port, one authenticated answer back, checked like the robot checks requests
// (structure, tag, sender 0 = the robot, and for a reply the echo of this request's sequence).
#pragma once

#include <cstdint>

#include "core/app/links/protocol_messages.hpp"
#include "core/base/result.hpp"

namespace rescue::app {

struct CtlTarget {
  std::uint32_t address{0};  // IPv4, network byte order
  std::uint16_t port{47010};
  protocol::Key key{};
  std::uint32_t sender{1};
  int timeout_ms{2000};
};

// Sends `request` (sequence: this host's Unix time in ns) and returns the robot's answer.
// Errors: timeout (no authentic answer in time; a robot holding another key stays silent),
// io_error.
Result<protocol::Message> ctl_exchange(const CtlTarget& target, protocol::Message request) noexcept;

}  // namespace rescue::app
