// Distributed-clock arithmetic of the bring-up (ETG.1000.4 section 9.3; the procedure SOEM's
// ec_configdc and IgH's ec_fsm_master follow): propagation delays through the tree from the port
// receive times latched by one broadcast write to 0x0900, and the system-time offsets.
//
// A frame enters every slave on port 0 and leaves it on the next open port in the order 0, 3, 1, 2;
// the slave latches the local time when the frame comes back on each port. So, for a slave S with
// child ports p1, p2, ... (in that order) and p0 = 0:
//
//   round trip through the child C on port pk:   RT = t_S[pk] - t_S[pk-1]
//   time the frame spent inside C's subtree:     sub(C) = t_C[last child port of C] - t_C[0]  (0 for a leaf)
//   one-way delay from S to C:                   (RT - sub(C)) / 2
//   delay(C) = delay(S) + (t_S[pk-1] - t_S[0]) + (RT - sub(C)) / 2,   delay(reference) = 0
//
// The middle term is the time the frame spent in the subtrees of C's elder siblings before S sent
// it to C (SOEM's dt2). The split of RT in two halves assumes equal forward and return delays.
//
// Differences are taken between latches of one slave only (its own 32-bit local clock, wrap-safe),
// so the clocks' offsets cancel and their drift over a few microseconds is negligible.
#pragma once

#include <array>
#include <cstdint>

#include "core/base/result.hpp"
#include "ecat/link/network_plan.hpp"

namespace rescue::ecat {

constexpr std::size_t kEscPorts = 4;
// Order in which an ESC forwards a frame through its ports.
constexpr std::array<std::uint8_t, kEscPorts> kPortProcessingOrder{0, 3, 1, 2};

struct PortReceiveTimes {
  std::array<std::uint32_t, kEscPorts> port{};  // 0x0900, 0x0904, 0x0908, 0x090C
};

using DcDelays = std::array<std::uint32_t, kMaxSlaves>;  // ns after the reference, per position

// Delays of every slave in `present` (which must include the reference, the first present slave
// in frame order, whose upstream chain is present). Fails when a slave's upstream is missing or a
// computed delay is negative (latch times inconsistent with the topology): detail0 = position.
Result<DcDelays> compute_propagation_delays(const NetworkPlan& plan, SlaveMask present,
                                            const std::array<PortReceiveTimes, kMaxSlaves>& times) noexcept;

// Ports of slave `position` that lead to a present child, in processing order, after port 0.
struct ChildPorts {
  std::array<std::uint8_t, kEscPorts> port{};
  std::array<std::uint8_t, kEscPorts> child{};
  std::uint8_t count{0};
};
ChildPorts child_ports(const NetworkPlan& plan, SlaveMask present, std::size_t position) noexcept;

// System-time offset (register 0x0920) that makes the slave's system time read `epoch + delay`
// at the instant its port 0 latched `local_receive_time` (0x0918): all slaves then agree on the
// system time of the same wave front, the reference reading `epoch`.
constexpr std::uint64_t system_time_offset(std::uint64_t epoch, std::uint32_t delay, std::uint64_t local_receive_time) noexcept {
  return epoch + delay - local_receive_time;  // modulo 2^64, as the ESC adds it
}

}  // namespace rescue::ecat
