// A cut cable at any of the 21 joints makes that joint and every joint after it on its branch
// unreachable (the upstream port closes, the frame comes back without them); all other slaves
// still answer. Restoring the cable brings them back.
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

TEST(LinkCut, EachJointTakesExactlyItsBranchTailAway) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  for (std::size_t joint = 0; joint < kJointCount; ++joint) {
    const std::size_t position = slave_position_of_joint(joint);
    ASSERT_TRUE(rig->segment.cut_link(position).ok());
    const JointMask lost = joints_lost_by_link_failure_at(joint);
    const auto count = static_cast<std::uint16_t>(__builtin_popcount(lost));

    const auto brd = rig->read(Command::BRD, 0, reg::kType, 1);
    ASSERT_TRUE(brd.returned) << kJoints[joint].name;
    EXPECT_EQ(brd.wkc, kSlaveCount - count) << "cut at " << kJoints[joint].name;
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      const bool gone = kSlaves[p].joint != kNoJoint && (lost & joint_bit(kSlaves[p].joint)) != 0;
      EXPECT_EQ(rig->read(Command::FPRD, kSlaves[p].station_address, reg::kType, 1).wkc, gone ? 0 : 1)
          << "cut at " << kJoints[joint].name << ", slave " << kSlaves[p].name;
    }
    // The slave upstream of the cut reports the link down and its port closed.
    const SlaveInfo& info = kSlaves[position];
    const std::uint16_t dl = rig->read16(kSlaves[info.upstream].station_address, reg::kDlStatus);
    EXPECT_EQ(dl & reg::dl_status_link(info.upstream_port), 0) << kJoints[joint].name;
    EXPECT_NE(dl & reg::dl_status_loop_closed(info.upstream_port), 0) << kJoints[joint].name;

    ASSERT_TRUE(rig->segment.restore_link(position).ok());
    EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount) << "restored " << kJoints[joint].name;
  }
}

TEST(LinkCut, CutBetweenJunctionsTakesBothOfItsBranchesAway) {
  auto rig = Rig::robot();
  ASSERT_TRUE(rig->segment.cut_link(1).ok());  // junction_b: right arm and lower body behind it
  const std::uint16_t behind = 1 + static_cast<std::uint16_t>(__builtin_popcount(joints_of_branch(Branch::right_arm) |
                                                                               joints_of_branch(Branch::lower_body)));
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount - behind);
}

TEST(LinkCut, CutAtTheMasterLosesTheFrame) {
  auto rig = Rig::robot();
  ASSERT_TRUE(rig->segment.cut_link(0).ok());
  EXPECT_FALSE(rig->read(Command::BRD, 0, reg::kType, 1).returned);
  EXPECT_EQ(rig->segment.counters().lost_no_link, 1u);
}

TEST(LinkCut, AutoCloseKeepsThePortClosedUntilTheMasterReopensIt) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  const std::size_t position = slave_position_of_joint(joint_index_by_name("l_elbow"));
  const std::uint16_t upstream = kSlaves[kSlaves[position].upstream].station_address;
  // Port 1 of the upstream joint on "auto close" (DL control loop bits 01).
  EXPECT_EQ(rig->write(Command::FPWR, upstream, reg::kDlControl, le32(0x00070001 | (1U << reg::dl_control_loop_shift(1)))).wkc, 1);
  ASSERT_TRUE(rig->segment.cut_link(position).ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount - 4);
  ASSERT_TRUE(rig->segment.restore_link(position).ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount - 4);  // link up, loop still closed
  EXPECT_EQ(rig->write(Command::FPWR, upstream, reg::kDlControl, le32(0x00070001 | (1U << reg::dl_control_loop_shift(1)))).wkc, 1);
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount);
}

TEST(LinkCut, PortForcedOpenWithoutLinkLosesTheFrame) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  // The last joint of the torso has no cable on port 1; forcing it open sends frames into nothing.
  const std::uint16_t neck_tilt = kSlaves[slave_position_of_joint(joint_index_by_name("neck_tilt"))].station_address;
  EXPECT_EQ(rig->write(Command::FPWR, neck_tilt, reg::kDlControl, le32(0x00070001 | (2U << reg::dl_control_loop_shift(1)))).wkc, 1);
  EXPECT_FALSE(rig->read(Command::BRD, 0, reg::kType, 1).returned);
  EXPECT_EQ(rig->segment.counters().lost_open_port, 1u);
}

}  // namespace
}  // namespace rescue::drivers::testing
