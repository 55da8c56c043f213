// The robot's network in the ring configuration (core/robot/robot_ring.hpp, docs/redundancy.md), as
// the master expects it: kRobotNetworkPlan's slaves, identities, process data and positions
// unchanged, each slave's cable (upstream, upstream_port) that of the line, and the ring-return
// cable's end (kRingReturnSlave's port kRingReturnPort, to the master's ring port). The process
// image layout is the tree's (branches are groups of joints, not cables).
#pragma once

#include "core/robot/robot_ring.hpp"
#include "drivers/joint/robot_network_plan.hpp"

namespace rescue::drivers {

constexpr ecat::NetworkPlan make_robot_ring_network_plan() noexcept {
  ecat::NetworkPlan plan = kRobotNetworkPlan;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    plan[p].upstream = kRingCabling[p].upstream;
    plan[p].upstream_port = kRingCabling[p].upstream_port;
  }
  return plan;
}

constexpr ecat::NetworkPlan kRobotRingNetworkPlan = make_robot_ring_network_plan();
static_assert(ecat::make_process_image_layout(kRobotRingNetworkPlan).total_bytes == kRobotImageBytes,
              "the ring's process image is the tree's");

}  // namespace rescue::drivers
