// Driving slaves through the EtherCAT state machine during bring-up (ETG.1000.6 section 6.4):
// request a state by writing AL control (0x0120), poll AL status (0x0130) and, when a slave
// refuses (error indication), read its AL status code (0x0134), acknowledge (AL control with the
// error-acknowledge bit) and ask again, a bounded number of times, within a timeout on the clock.
#pragma once

#include <cstdint>

#include "core/base/result.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/link/datagram_link.hpp"
#include "ecat/link/network_plan.hpp"

namespace rescue::ecat {

struct AlOptions {
  hal::Nanoseconds frame_timeout{2 * hal::kNsPerMs};
  hal::Nanoseconds state_timeout{3 * hal::kNsPerSec};  // per transition (ETG.1020 suggests seconds)
  hal::Nanoseconds poll_interval{100 * hal::kNsPerUs};
  unsigned retries{2};  // requests after a refusal
};

// The slave that kept the network from reaching a state, and why.
struct AlFailure {
  std::uint8_t position{0xFF};     // planned position
  reg::AlState requested{reg::AlState::none};
  std::uint16_t al_status{0};      // last AL status register
  std::uint16_t al_status_code{0}; // last AL status code (0 when none was given)
  bool timed_out{false};
  bool unreachable{false};
};

// Brings every slave of `slaves` to `state`. On failure returns Errc::refused ("slave refused
// state"), Errc::timeout or Errc::io_error and fills `failure` for the first slave concerned.
Status request_al_state(DatagramLink& link, const NetworkPlan& plan, SlaveMask slaves, reg::AlState state,
                        const AlOptions& options, AlFailure& failure) noexcept;

// Reads the AL status (and code) of each slave of `slaves`; unreachable ones get status 0.
struct AlSnapshot {
  std::array<std::uint16_t, kMaxSlaves> status{};
  std::array<std::uint16_t, kMaxSlaves> code{};
  SlaveMask answered{0};
};
Result<AlSnapshot> read_al_status(DatagramLink& link, const NetworkPlan& plan, SlaveMask slaves,
                                  hal::Nanoseconds frame_timeout) noexcept;

// "l_elbow refused SAFE-OP: AL status 0x0012 (PRE-OP, error), code 0x001d invalid output configuration"
std::size_t describe(const AlFailure& failure, const NetworkPlan& plan, char* out, std::size_t size) noexcept;

}  // namespace rescue::ecat
