// The master on the simulated robot, a link cut at each of the 21 joints in turn (while running in
// OP at 1 kHz): the report names exactly the joint and everything behind it on its branch, within a
// few cycles of the cut; every healthy joint's inputs stay valid in every cycle, including the
// cut's own; the restored link is reported and the joints stay out of the exchange.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

class CutAtJoint : public ::testing::TestWithParam<std::size_t> {
 protected:
  void SetUp() override {
    rig = std::make_unique<SimulatedRobotRig>();
    ASSERT_TRUE(rig->bus.bring_up(testing::fast_options()).ok());
    for (int i = 0; i < 200 && rig->bus.master().state() != MasterState::op; ++i) (void)cycle();
    ASSERT_EQ(rig->bus.master().state(), MasterState::op);
    for (int i = 0; i < 5; ++i) ASSERT_EQ(cycle().valid, kAllJoints);
  }
  drivers::JointCycleResult cycle() { return rig->cycle(refs, feedback); }

  std::unique_ptr<SimulatedRobotRig> rig;
  drivers::JointReferences refs{};
  drivers::JointFeedback feedback{};
};

TEST_P(CutAtJoint, ReportsItsLinkFailureSetAndHealthyJointsMissNoCycle) {
  const std::size_t joint = GetParam();
  const JointMask lost = joints_lost_by_link_failure_at(joint);
  const JointMask healthy = kAllJoints & ~lost;
  ASSERT_TRUE(rig->segment.cut_link(slave_position_of_joint(joint)).ok());
  const std::uint64_t cut_cycle = rig->bus.master().cycles() + 1;

  std::vector<LinkReport> reports;
  for (int i = 0; i < 20; ++i) {
    const drivers::JointCycleResult r = cycle();
    ASSERT_TRUE(r.frame_received);
    EXPECT_EQ(r.valid & healthy, healthy) << "a healthy joint missed cycle " << r.cycle;
    EXPECT_EQ(r.valid & lost, 0u) << "an unreachable joint was valid in cycle " << r.cycle;
    LinkReport report;
    while (rig->bus.master().pop_report(report)) reports.push_back(report);
  }
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].kind, LinkEventKind::lost);
  EXPECT_EQ(drivers::joints_of_slaves(reports[0].slaves), lost);
  EXPECT_EQ(reports[0].detected_cycle, cut_cycle);
  EXPECT_LE(reports[0].cycle, cut_cycle + 2);
  EXPECT_EQ(reports[0].branch, static_cast<std::uint8_t>(kJoints[joint].branch));

  // Link back: noticed and reported, the joints stay out of the exchange with silent outputs.
  ASSERT_TRUE(rig->segment.restore_link(slave_position_of_joint(joint)).ok());
  JointMask restored = 0;
  for (int i = 0; i < 40; ++i) {
    const drivers::JointCycleResult r = cycle();
    EXPECT_EQ(r.valid & healthy, healthy);
    EXPECT_EQ(r.valid & lost, 0u) << "restored joints used without re-integration";
    LinkReport report;
    while (rig->bus.master().pop_report(report)) {
      EXPECT_EQ(report.kind, LinkEventKind::restored);
      restored |= drivers::joints_of_slaves(report.slaves);
    }
  }
  EXPECT_EQ(restored, lost);
  EXPECT_EQ(rig->bus.master().monitor().restored(), drivers::slaves_of_joints(lost));
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    (void)cycle();
    EXPECT_EQ(rig->bus.last_cycle().branch_wkc[b], rig->bus.last_cycle().expected_wkc[b]) << "restored slaves add nothing to the counters";
  }
}

INSTANTIATE_TEST_SUITE_P(EveryJoint, CutAtJoint, ::testing::Range<std::size_t>(0, kJointCount),
                         [](const ::testing::TestParamInfo<std::size_t>& param) { return std::string(kJoints[param.param].name); });

}  // namespace
}  // namespace rescue::ecat
