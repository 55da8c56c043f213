// A redundant link over the two-port fake segment (two_port_segment.hpp) and a one-branch plan of its
// slaves (station kStation0 + i, a byte of outputs and one of inputs each, named s0, s1, ...): what
// the ring monitor's and the link monitor's tests exchange their frames through.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecat/link/datagram_link.hpp"
#include "ecat/link/network_plan.hpp"
#include "tests/support/two_port_segment.hpp"

namespace rescue::test {

constexpr std::size_t kRingRigSlaves = 6;

inline ecat::NetworkPlan ring_rig_plan() {
  static constexpr std::array<const char*, kRingRigSlaves> kNames{"s0", "s1", "s2", "s3", "s4", "s5"};
  ecat::NetworkPlan plan{};
  for (std::size_t i = 0; i < kRingRigSlaves; ++i) {
    ecat::SlavePlan& s = plan[i];
    s.name = kNames[i];
    s.device_name = "fake";
    s.station_address = static_cast<std::uint16_t>(TwoPortSegment::kStation0 + i);
    s.upstream = i == 0 ? ecat::kMasterUpstream : static_cast<std::uint8_t>(i - 1);
    s.upstream_port = 1;
    s.branch = 0;
    s.output_bytes = 1;
    s.input_bytes = 1;
  }
  for (std::size_t i = kRingRigSlaves; i < ecat::kMaxSlaves; ++i) plan[i].branch = ecat::kNoBranch;
  return plan;
}

struct TwoPortRig {
  TwoPortRig() { link.set_ring(&segment.ring()); }
  TwoPortSegment segment{kRingRigSlaves};
  ecat::DatagramLink link{segment.main()};
  ecat::NetworkPlan plan{ring_rig_plan()};
  ecat::ProcessImageLayout layout{ecat::make_process_image_layout(plan)};
};

}  // namespace rescue::test
