// Re-integration after a restored link, on the simulated robot: the joints behind a cut drop to
// SAFE-OP when their process-data watchdog expires; when the link is back they are reported
// restored and stay out; only an explicit reintegrate() brings them back to OP and into the
// exchange (reported), after which their drives can be enabled again. Asking for joints that are
// not restored is refused.
#include <gtest/gtest.h>

#include <memory>

#include "drivers/cia402/cia402_enable.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

TEST(MasterReintegration, RestoredJointsComeBackOnlyWhenAsked) {
  auto rig = std::make_unique<SimulatedRobotRig>();
  ASSERT_TRUE(rig->bus.bring_up(testing::fast_options()).ok());
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  for (int i = 0; i < 200 && rig->bus.master().state() != MasterState::op; ++i) (void)rig->cycle(refs, fb);
  ASSERT_EQ(rig->bus.master().state(), MasterState::op);

  const std::size_t elbow = joint_index_by_name("l_elbow");
  const JointMask lost = joints_lost_by_link_failure_at(elbow);
  const std::size_t position = slave_position_of_joint(elbow);
  ASSERT_TRUE(rig->segment.cut_link(position).ok());
  for (int i = 0; i < 300; ++i) (void)rig->cycle(refs, fb);  // the drives' watchdogs expire meanwhile
  EXPECT_EQ(rig->segment.esc(position).al_state(), reg::AlState::safe_op);
  EXPECT_FALSE(rig->bus.reintegrate(lost)) << "lost joints are not restored yet";

  ASSERT_TRUE(rig->segment.restore_link(position).ok());
  JointMask restored = 0;
  LinkReport report;
  for (int i = 0; i < 40; ++i) {
    (void)rig->cycle(refs, fb);
    while (rig->bus.master().pop_report(report)) {
      if (report.kind == LinkEventKind::restored) restored |= drivers::joints_of_slaves(report.slaves);
    }
  }
  ASSERT_EQ(restored, lost);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(rig->cycle(refs, fb).valid & lost, 0u);

  ASSERT_TRUE(rig->bus.reintegrate(lost));
  EXPECT_FALSE(rig->bus.reintegrate(lost)) << "one re-integration at a time";
  JointMask back = 0;
  int cycles = 0;
  for (; cycles < 50 && back != lost; ++cycles) {
    const drivers::JointCycleResult r = rig->cycle(refs, fb);
    EXPECT_EQ(r.valid & ~lost, kAllJoints & ~lost) << "healthy joints keep every cycle";
    while (rig->bus.master().pop_report(report)) {
      ASSERT_EQ(report.kind, LinkEventKind::reintegrated) << to_string(report.kind);
      back |= drivers::joints_of_slaves(report.slaves);
    }
  }
  ASSERT_EQ(back, lost);
  EXPECT_LE(cycles, 10);
  const drivers::JointCycleResult r = rig->cycle(refs, fb);
  EXPECT_EQ(r.valid, kAllJoints);
  EXPECT_EQ(r.out, 0u);
  for (std::size_t b = 0; b < kMaxBranches; ++b) EXPECT_EQ(rig->bus.last_cycle().branch_wkc[b], rig->bus.last_cycle().expected_wkc[b]);
  EXPECT_EQ(rig->segment.esc(position).al_state(), reg::AlState::op);

  // Its drive is enabled again like any other.
  refs[elbow].mode_of_operation = static_cast<std::int8_t>(ControlMode::cyclic_position);
  refs[elbow].target_position = fb.joints[elbow].position_actual;
  for (int i = 0; i < 100 && !drivers::is_enabled(fb.joints[elbow].statusword); ++i) {
    refs[elbow].controlword = drivers::controlword_towards_enabled(fb.joints[elbow].statusword, refs[elbow].controlword);
    (void)rig->cycle(refs, fb);
  }
  EXPECT_TRUE(drivers::is_enabled(fb.joints[elbow].statusword));
}

}  // namespace
}  // namespace rescue::ecat
