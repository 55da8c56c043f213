// The operator client's exchange (rescue-motion ctl, docs/operator.md): first get_epoch, whose
// authenticated answer (the request's sequence echoed) gives the robot's epoch and robot id; then
// the request, for that robot in that epoch, and its authenticated answer, checked like the robot
// checks requests (structure, tag, sender 0 = the robot, the same robot id and epoch, and for a
// reply the echo of this request's sequence). Both round trips share one deadline (--timeout).
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
  std::uint32_t robot{protocol::kAnyRobot};  // --robot: refuse a robot with another id (kAnyRobot: whichever answers)
  int timeout_ms{2000};
};

// Sends `request` (sequence: this host's Unix time in ns) and returns the robot's answer.
// Errors: timeout (no authentic answer in time; a robot holding another key stays silent; the
// message says when the robot answered get_epoch and only the request went unanswered),
// refused (the robot that answered has another robot id than target.robot), io_error.
Result<protocol::Message> ctl_exchange(const CtlTarget& target, protocol::Message request) noexcept;

}  // namespace rescue::app
