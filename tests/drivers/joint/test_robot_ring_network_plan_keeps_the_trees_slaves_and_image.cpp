// The master's plan of the ring configuration (drivers/joint/robot_ring_network_plan.hpp) is the
// tree's plan with each slave's cable that of the line (core/robot/robot_ring.hpp): same slaves,
// identities, station addresses, branches and process image; each slave hangs off the one before it,
// by port 3 of a junction or port 1 of a joint; the ring cable ends at l_hand's free port 1. The
// simulated ring segment is cabled the same way.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <memory>

#include "core/robot/robot_ring.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"

namespace rescue::drivers {
namespace {

TEST(RobotRingPlan, KeepsTheTreesSlavesIdentitiesAndImage) {
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    const ecat::SlavePlan& ring = kRobotRingNetworkPlan[p];
    const ecat::SlavePlan& tree = kRobotNetworkPlan[p];
    EXPECT_STREQ(ring.name, tree.name);
    EXPECT_EQ(ring.product_code, tree.product_code);
    EXPECT_EQ(ring.station_address, tree.station_address);
    EXPECT_EQ(ring.branch, tree.branch);
    EXPECT_EQ(ring.output_bytes, tree.output_bytes);
    EXPECT_EQ(ring.input_bytes, tree.input_bytes);
  }
  const ecat::ProcessImageLayout ring_layout = ecat::make_process_image_layout(kRobotRingNetworkPlan);
  EXPECT_EQ(ring_layout.total_bytes, kRobotImageLayout.total_bytes);
}

TEST(RobotRingPlan, EachSlaveHangsOffTheOneBeforeIt) {
  EXPECT_EQ(kRobotRingNetworkPlan[0].upstream, ecat::kMasterUpstream);
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    EXPECT_EQ(kRobotRingNetworkPlan[p].upstream, p - 1) << kSlaves[p].name;
    EXPECT_EQ(kRobotRingNetworkPlan[p].upstream_port, kSlaves[p - 1].kind == SlaveKind::junction ? 3 : 1) << kSlaves[p].name;
  }
  EXPECT_STREQ(kSlaves[kRingReturnSlave].name, "l_hand");
  EXPECT_EQ(kRingReturnPort, 1);
}

TEST(RobotRingPlan, TheSimulatedRingIsCabledAsThePlanSays) {
  RobotSegmentOptions options;
  options.ring = true;
  auto robot = std::make_unique<SimulatedRobot>(options);
  ASSERT_TRUE(robot->status().ok());
  const SimulatedSegment& segment = robot->segment();
  ASSERT_TRUE(segment.has_ring());
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    EXPECT_EQ(segment.slave(p).upstream, kRobotRingNetworkPlan[p].upstream) << kSlaves[p].name;
    EXPECT_EQ(segment.slave(p).upstream_port, kRobotRingNetworkPlan[p].upstream_port) << kSlaves[p].name;
  }
  EXPECT_EQ(segment.ring_cable().position, kRingReturnSlave);
  EXPECT_EQ(segment.ring_cable().port, kRingReturnPort);
}

}  // namespace
}  // namespace rescue::drivers
