#include "ecat/dc/dc_delay.hpp"

namespace rescue::ecat {
namespace {

std::uint32_t u32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

// Time between two latches of the same slave (its 32-bit clock wraps every 4.3 s).
std::int64_t elapsed(std::uint32_t from, std::uint32_t to) noexcept {
  return static_cast<std::int64_t>(static_cast<std::uint32_t>(to - from));
}

}  // namespace

ChildPorts child_ports(const NetworkPlan& plan, SlaveMask present, std::size_t position) noexcept {
  ChildPorts ports{};
  for (std::size_t k = 1; k < kEscPorts; ++k) {
    const std::uint8_t port = kPortProcessingOrder[k];
    for (std::size_t c = position + 1; c < kMaxSlaves; ++c) {
      if ((present & slave_bit(c)) == 0) continue;
      if (plan[c].upstream == position && plan[c].upstream_port == port) {
        ports.port[ports.count] = port;
        ports.child[ports.count] = static_cast<std::uint8_t>(c);
        ++ports.count;
        break;  // one cable per port
      }
    }
  }
  return ports;
}

Result<DcDelays> compute_propagation_delays(const NetworkPlan& plan, SlaveMask present,
                                            const std::array<PortReceiveTimes, kMaxSlaves>& times) noexcept {
  DcDelays delays{};
  // Time each present slave's subtree held the frame: from its port 0 latch to its last child's return.
  std::array<std::int64_t, kMaxSlaves> subtree{};
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((present & slave_bit(p)) == 0) continue;
    const ChildPorts ports = child_ports(plan, present, p);
    if (ports.count > 0) subtree[p] = elapsed(times[p].port[0], times[p].port[ports.port[ports.count - 1]]);
  }
  bool reference_seen = false;
  // Upstream slaves come first in frame order, so one pass in that order sees each parent first.
  for (std::size_t s = 0; s < kMaxSlaves; ++s) {
    if ((present & slave_bit(s)) == 0) continue;
    if (!reference_seen) {
      reference_seen = true;
      delays[s] = 0;
    } else if (plan[s].upstream == kMasterUpstream || (present & slave_bit(plan[s].upstream)) == 0) {
      return make_error(Errc::mismatch, "slave present without its upstream slave", u32(s));
    }
    const ChildPorts ports = child_ports(plan, present, s);
    std::uint32_t previous = times[s].port[0];
    for (std::size_t k = 0; k < ports.count; ++k) {
      const std::uint32_t back = times[s].port[ports.port[k]];
      const std::int64_t round_trip = elapsed(previous, back);
      const std::size_t child = ports.child[k];
      const std::int64_t one_way = (round_trip - subtree[child]) / 2;
      if (one_way < 0) return make_error(Errc::malformed, "negative propagation delay", u32(child), ports.port[k]);
      const std::int64_t siblings = elapsed(times[s].port[0], previous);
      delays[child] = delays[s] + static_cast<std::uint32_t>(siblings + one_way);
      previous = back;
    }
  }
  if (!reference_seen) return make_error(Errc::invalid_argument, "no slave present");
  return delays;
}

}  // namespace rescue::ecat
