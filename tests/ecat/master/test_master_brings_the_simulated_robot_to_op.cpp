// The master against the simulated robot on virtual time: bring-up from power-on to OP with every
// slave identified, addressed, configured and synchronised, then cycles in which every joint's
// inputs come back valid and the drives follow the outputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "drivers/cia402/cia402_enable.hpp"
#include "tests/support/simulated_robot_rig.hpp"
#include "drivers/joint/joint_units.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

std::string describe_failure(const Master& m) { return testing::describe_master_failure(m); }

TEST(MasterOnSimulatedRobot, BringsEverySlaveToOp) {
  auto rig = std::make_unique<SimulatedRobotRig>();
  ASSERT_TRUE(rig->built.ok()) << rig->built.error().what;
  Master& master = rig->bus.master();
  const Status up = rig->bus.bring_up(testing::fast_options());
  ASSERT_TRUE(up.ok()) << describe_failure(master);
  EXPECT_EQ(master.report().slaves_counted, kSlaveCount);
  EXPECT_EQ(master.operated(), kAllSlaves);
  EXPECT_TRUE(master.report().match.differences.empty());
  EXPECT_EQ(master.state(), MasterState::going_op);

  drivers::JointReferences refs{};
  drivers::JointFeedback feedback{};
  drivers::JointCycleResult r;
  for (int i = 0; i < 200 && master.state() != MasterState::op; ++i) r = rig->cycle(refs, feedback);
  ASSERT_EQ(master.state(), MasterState::op) << describe_failure(master);
  for (int i = 0; i < 50; ++i) {
    r = rig->cycle(refs, feedback);
    ASSERT_TRUE(r.frame_received);
    EXPECT_EQ(r.valid, kAllJoints) << "cycle " << r.cycle;
    for (std::size_t b = 0; b < kMaxBranches; ++b) EXPECT_EQ(rig->bus.last_cycle().branch_wkc[b], rig->bus.last_cycle().expected_wkc[b]);
  }
  LinkReport report;
  EXPECT_FALSE(master.pop_report(report)) << to_string(report.kind);
  std::printf("bring-up: %.3f ms to SAFE-OP, %.3f ms to OP, %llu frames, DC max diff %u ns\n",
              static_cast<double>(master.report().safe_op_at - master.report().started_at) / 1e6,
              static_cast<double>(master.report().op_at - master.report().started_at) / 1e6,
              static_cast<unsigned long long>(master.report().frames), master.report().dc_max_difference_ns);
}

TEST(MasterOnSimulatedRobot, EnablesEveryDriveAndTheJointsFollowTheirTargets) {
  auto rig = std::make_unique<SimulatedRobotRig>();
  ASSERT_TRUE(rig->bus.bring_up(testing::fast_options()).ok()) << describe_failure(rig->bus.master());
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  for (int i = 0; i < 200 && rig->bus.master().state() != MasterState::op; ++i) (void)rig->cycle(refs, fb);
  ASSERT_EQ(rig->bus.master().state(), MasterState::op);
  (void)rig->cycle(refs, fb);
  ASSERT_EQ(fb.valid, kAllJoints);

  // CiA 402 enable sequence, holding each joint where it is (cyclic position / velocity).
  std::array<std::int32_t, kJointCount> hold{};
  for (std::size_t j = 0; j < kJointCount; ++j) hold[j] = fb.joints[j].position_actual;
  JointMask enabled = 0;
  for (int i = 0; i < 20 && enabled != kAllJoints; ++i) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      refs[j].mode_of_operation = static_cast<std::int8_t>(kJoints[j].default_mode);
      refs[j].target_position = hold[j];
      refs[j].target_velocity = 0;
      refs[j].controlword = drivers::controlword_towards_enabled(fb.joints[j].statusword, refs[j].controlword);
    }
    (void)rig->cycle(refs, fb);
    enabled = 0;
    for (std::size_t j = 0; j < kJointCount; ++j) enabled |= drivers::is_enabled(fb.joints[j].statusword) ? joint_bit(j) : 0;
  }
  ASSERT_EQ(enabled, kAllJoints);

  // The elbow moves 0.2 rad in 0.5 s; every other joint holds.
  const std::size_t elbow = joint_index_by_name("l_elbow");
  const std::int32_t goal = hold[elbow] + drivers::rad_to_counts(0.2);
  for (int i = 0; i < 1000; ++i) {
    const double f = std::min(1.0, i / 500.0);
    refs[elbow].target_position = hold[elbow] + static_cast<std::int32_t>(f * (goal - hold[elbow]));
    const drivers::JointCycleResult r = rig->cycle(refs, fb);
    ASSERT_EQ(r.valid, kAllJoints);
  }
  EXPECT_NEAR(fb.joints[elbow].position_actual, goal, drivers::rad_to_counts(0.002));
  const std::size_t neck = joint_index_by_name("neck_pan");
  EXPECT_NEAR(fb.joints[neck].position_actual, hold[neck], drivers::rad_to_counts(0.002));
  EXPECT_EQ(fb.joints[elbow].mode_display, static_cast<std::int8_t>(ControlMode::cyclic_position));
}

}  // namespace
}  // namespace rescue::ecat
