// An RC task's input is a record of the shared segment (the parser's queue to it). A kind, effector
// or hand action the parser never writes, or a pose the operator's protocol refuses, is damage (a
// stray write, a bit flip): refused and counted, the task goes on as before; the next whole input
// is taken.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "tests/support/rc_task_rig.hpp"

namespace rescue::app {
namespace {

const auto kRightHand = static_cast<Eigen::Index>(joint_index_by_name("r_hand"));
const auto kLeftHand = static_cast<Eigen::Index>(joint_index_by_name("l_hand"));
constexpr auto kClose = static_cast<std::uint8_t>(protocol::HandAction::close);

TEST(RcTaskDamagedInput, AHandInputOfAnUnknownEffectorMovesNoHand) {
  testing::RcTaskRig rig;
  rig.steps(5);
  ASSERT_TRUE(rig.send(RcTaskId::teleop, RcInputKind::hand, 7, kClose));  // read as it was: the right hand
  rig.steps(50);
  EXPECT_EQ(rig.teleop->counters().damaged_inputs, 1U);
  EXPECT_DOUBLE_EQ(rig.teleop->references()(kRightHand), 0.0);
  EXPECT_DOUBLE_EQ(rig.teleop->references()(kLeftHand), 0.0);
  // A whole input afterwards is taken.
  ASSERT_TRUE(rig.send(RcTaskId::teleop, RcInputKind::hand, 1, kClose));
  rig.steps(50);
  EXPECT_GT(rig.teleop->references()(kRightHand), 0.0);
  EXPECT_EQ(rig.teleop->counters().damaged_inputs, 1U);
}

TEST(RcTaskDamagedInput, AHandActionOfAnUnknownValueIsRefused) {
  testing::RcTaskRig rig;
  rig.steps(5);
  ASSERT_TRUE(rig.send(RcTaskId::teleop, RcInputKind::hand, 1, 0x40));  // read as it was: open
  rig.steps(50);
  EXPECT_EQ(rig.teleop->counters().damaged_inputs, 1U);
  EXPECT_DOUBLE_EQ(rig.teleop->references()(kRightHand), 0.0);
}

TEST(RcTaskDamagedInput, ATargetWithANonFinitePoseOrOneBeyondReachLeavesTheTaskAsItWas) {
  testing::RcTaskRig rig;
  rig.steps(5);
  ASSERT_EQ(rig.rescue->mode(), RcMode::idle);
  std::array<double, 6> pose{0.3, 0.2, 0.5, 0.0, 0.0, 0.0};
  pose[1] = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::end_effector_target, 0, 0, pose));
  pose[1] = 1e300;
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::end_effector_target, 0, 0, pose));
  pose[1] = 0.2;
  pose[5] = 4.0;  // yaw beyond pi
  ASSERT_TRUE(rig.send(RcTaskId::rescue, RcInputKind::end_effector_target, 0, 0, pose));
  rig.step();
  EXPECT_EQ(rig.rescue->counters().damaged_inputs, 3U);
  EXPECT_EQ(rig.rescue->mode(), RcMode::idle);
}

TEST(RcTaskDamagedInput, AnInputOfAnUnknownKindIsCountedAsDamage) {
  testing::RcTaskRig rig;
  rig.steps(5);
  RcTaskInput input;
  const std::uint8_t byte = 0x33;
  std::memcpy(&input.kind, &byte, 1);  // as a stray write leaves it in the segment
  ASSERT_TRUE(rig.links->rc_inputs[0].try_push(input));
  rig.step();
  EXPECT_EQ(rig.rescue->counters().damaged_inputs, 1U);
  EXPECT_EQ(rig.rescue->mode(), RcMode::idle);
}

}  // namespace
}  // namespace rescue::app
