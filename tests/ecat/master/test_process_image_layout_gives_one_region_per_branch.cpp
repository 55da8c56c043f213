// The robot's logical process image: one contiguous region per branch (outputs, then inputs, in
// wiring order), regions back to back, every joint's data exactly once, junctions absent.
#include <gtest/gtest.h>

#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/link/network_plan.hpp"

namespace rescue::ecat {
namespace {

using drivers::kRobotImageLayout;
using drivers::kRobotNetworkPlan;

TEST(ProcessImageLayout, BranchRegionsAreContiguousAndInBranchOrder) {
  std::uint32_t next = 0;
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    const BranchLayout& branch = kRobotImageLayout.branches[b];
    EXPECT_EQ(branch.logical_start, next) << to_string(static_cast<Branch>(b));
    EXPECT_EQ(branch.slave_count, popcount(joints_of_branch(static_cast<Branch>(b))));
    EXPECT_EQ(branch.output_length, branch.slave_count * drivers::kJointOutputBytes);
    EXPECT_EQ(branch.length, branch.slave_count * (drivers::kJointOutputBytes + drivers::kJointInputBytes));
    next += branch.length;
  }
  EXPECT_EQ(kRobotImageLayout.total_bytes, next);
  EXPECT_EQ(kRobotImageLayout.total_bytes, 21u * 28u);
}

TEST(ProcessImageLayout, SlavesOfABranchAreInWiringOrder) {
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    const BranchLayout& branch = kRobotImageLayout.branches[b];
    for (std::size_t i = 0; i < branch.slave_count; ++i) {
      const SlavePlan& s = kRobotNetworkPlan[branch.slaves[i]];
      const std::uint8_t joint = drivers::kJointOfSlave[branch.slaves[i]];
      ASSERT_NE(joint, kNoJoint);
      EXPECT_EQ(kJoints[joint].order_on_branch, i) << s.name;
      const SlaveImage& image = kRobotImageLayout.slaves[branch.slaves[i]];
      EXPECT_EQ(image.output_offset, branch.logical_start + i * drivers::kJointOutputBytes) << s.name;
      EXPECT_EQ(image.input_offset, branch.logical_start + branch.output_length + i * drivers::kJointInputBytes) << s.name;
    }
  }
}

TEST(ProcessImageLayout, EveryImageByteBelongsToExactlyOneJoint) {
  std::array<int, drivers::kRobotImageBytes> owner{};
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    const SlavePlan& s = kRobotNetworkPlan[p];
    const SlaveImage& image = kRobotImageLayout.slaves[p];
    for (std::size_t i = 0; i < s.output_bytes; ++i) ++owner[image.output_offset + i];
    for (std::size_t i = 0; i < s.input_bytes; ++i) ++owner[image.input_offset + i];
  }
  for (int n : owner) EXPECT_EQ(n, 1);
}

TEST(ProcessImageLayout, JunctionsHaveNoProcessDataAndNoBranch) {
  EXPECT_EQ(kRobotNetworkPlan[0].branch, kNoBranch);
  EXPECT_EQ(kRobotNetworkPlan[1].branch, kNoBranch);
  EXPECT_EQ(kRobotNetworkPlan[0].output_bytes + kRobotNetworkPlan[0].input_bytes, 0);
  EXPECT_FALSE(kRobotNetworkPlan[1].mailbox);
}

TEST(ProcessImageLayout, SubtreeOfAJointIsItsLinkFailureSet) {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::size_t p = slave_position_of_joint(j);
    EXPECT_EQ(drivers::joints_of_slaves(subtree_of(kRobotNetworkPlan, p)), joints_lost_by_link_failure_at(j))
        << kJoints[j].name;
  }
  // junction_b carries the right arm and the lower body.
  EXPECT_EQ(drivers::joints_of_slaves(subtree_of(kRobotNetworkPlan, 1)),
            joints_of_branch(Branch::right_arm) | joints_of_branch(Branch::lower_body));
}

}  // namespace
}  // namespace rescue::ecat
