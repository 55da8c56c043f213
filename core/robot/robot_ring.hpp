// The robot's ring configuration (docs/redundancy.md): the same 23 slaves in the same processing
// order (kSlaves), cabled as ONE line through every slave, closed back from the last slave's free
// port to the master's second (ring) port:
//
//   master main - junction_a:0  junction_a:3 - junction_b:0  junction_b:3 - r_shoulder_pitch:0
//   ... each joint's port 1 to the next slave's port 0, in kSlaves order ...
//   l_hand:1 - master ring
//
// Every cable lies on the one ring, so any single cut loses no slave (the frames from the two master
// ports each reach the slaves on their side). The junctions pass the line on from port 0 to port 3;
// their ports 1 and 2 stay free. The default robot stays the paper's tree (kSlaves' own cabling).
#pragma once

#include <array>
#include <cstdint>

#include "core/robot/robot.hpp"

namespace rescue {

struct RingCabling {
  std::uint8_t upstream;       // kMasterUpstream for the first slave
  std::uint8_t upstream_port;  // the upstream slave's port the line leaves by
};

// A junction passes the line on by its port 3 (the first port after port 0), a joint by its port 1.
constexpr std::uint8_t ring_line_out_port(SlaveKind kind) noexcept { return kind == SlaveKind::junction ? 3 : 1; }

constexpr std::array<RingCabling, kSlaveCount> make_ring_cabling() noexcept {
  std::array<RingCabling, kSlaveCount> cabling{};
  cabling[0] = RingCabling{kMasterUpstream, 0};
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    cabling[p] = RingCabling{static_cast<std::uint8_t>(p - 1), ring_line_out_port(kSlaves[p - 1].kind)};
  }
  return cabling;
}

// Position p's cable in the ring configuration (replaces kSlaves[p].upstream / upstream_port).
constexpr std::array<RingCabling, kSlaveCount> kRingCabling = make_ring_cabling();

// The ring-return cable: from this slave's port to the master's ring port.
constexpr std::uint8_t kRingReturnSlave = static_cast<std::uint8_t>(kSlaveCount - 1);
constexpr std::uint8_t kRingReturnPort = ring_line_out_port(kSlaves[kSlaveCount - 1].kind);

static_assert(kSlaves[0].upstream == kMasterUpstream, "the line starts at the tree's first slave");

}  // namespace rescue
