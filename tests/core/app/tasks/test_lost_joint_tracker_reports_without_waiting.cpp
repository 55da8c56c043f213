// The EtherCAT handler's side of reconfiguration on its own: the joints the master takes out of the
// exchange (its link monitor alone confirms a loss, tests/ecat/master/) are excluded at once,
// reported without waiting (a full queue is retried next cycle), and confirmed or cleared by the
// joint manager's notices.
#include <gtest/gtest.h>

#include "core/app/tasks/lost_joint_tracker.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

using testing::FakeQueue;

const JointMask kElbowCut = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));
const JointMask kTorso = joints_of_branch(Branch::torso);

struct TrackerRig {
  explicit TrackerRig(JointMask restored = 0) : tracker(reports, notices, restored) {}
  void cycles(int n, JointMask unreachable) {
    for (int i = 0; i < n; ++i) {
      ++cycle;
      tracker.on_cycle(cycle, static_cast<hal::Nanoseconds>(cycle) * hal::kNsPerMs, unreachable);
    }
  }
  FakeQueue<LostJointsReport> reports;
  FakeQueue<JointManagerNotice> notices;
  LostJointTracker tracker;
  std::uint64_t cycle{0};
};

TEST(LostJointTracker, TheCycleTheMasterTakesJointsOutExcludesAndReportsThemAtOnce) {
  TrackerRig rig;
  rig.cycles(2, 0);
  EXPECT_EQ(rig.tracker.excluded(), 0u);
  EXPECT_EQ(rig.reports.size(), 0u);
  rig.cycles(1, kElbowCut);
  EXPECT_EQ(rig.tracker.pending(), kElbowCut);
  EXPECT_EQ(rig.tracker.excluded(), kElbowCut);
  LostJointsReport report;
  ASSERT_TRUE(rig.reports.try_receive(report));
  EXPECT_EQ(report.lost, kElbowCut);
  EXPECT_EQ(report.cycle, 3u);
  EXPECT_EQ(report.detected_at, 3 * hal::kNsPerMs);
  rig.cycles(10, kElbowCut);
  EXPECT_EQ(rig.reports.size(), 0u);  // reported once
}

TEST(LostJointTracker, FullReportQueueIsRetriedNextCycleWithEveryLostJoint) {
  TrackerRig rig;
  rig.reports.set_capacity(0);
  rig.cycles(2, 0);
  rig.cycles(1, kElbowCut);
  EXPECT_EQ(rig.tracker.unreported(), kElbowCut);
  EXPECT_EQ(rig.tracker.excluded(), kElbowCut);  // excluded even before it could report
  rig.cycles(3, kElbowCut | kTorso);
  EXPECT_EQ(rig.tracker.reports_deferred(), 4u);  // cycles 3..6: one attempt each
  rig.reports.set_capacity(4);
  rig.cycles(1, kElbowCut | kTorso);
  LostJointsReport report;
  ASSERT_TRUE(rig.reports.try_receive(report));
  EXPECT_EQ(report.lost, kElbowCut | kTorso);
  EXPECT_EQ(rig.tracker.pending(), kElbowCut | kTorso);
}

TEST(LostJointTracker, AnswerConfirmsAndClearCommandsAgain) {
  TrackerRig rig;
  rig.cycles(3, kElbowCut);
  ASSERT_TRUE(rig.notices.try_send(JointManagerNotice{NoticeKind::lost_joints_recorded, kElbowCut, 3, Errc::ok}));
  rig.cycles(1, kElbowCut);
  EXPECT_EQ(rig.tracker.pending(), 0u);
  EXPECT_EQ(rig.tracker.confirmed(), kElbowCut);
  EXPECT_EQ(rig.tracker.last_answer_cycle(), 3u);

  const JointMask hand = joint_bit(joint_index_by_name("l_hand"));
  ASSERT_TRUE(rig.notices.try_send(JointManagerNotice{NoticeKind::joints_cleared, hand, 0, Errc::ok}));
  rig.cycles(1, kElbowCut & ~hand);
  EXPECT_EQ(rig.tracker.excluded(), kElbowCut & ~hand);
}

TEST(LostJointTracker, RestoredJointsAreExcludedFromTheFirstCycleAndNotReported) {
  TrackerRig rig(kElbowCut);
  EXPECT_EQ(rig.tracker.excluded(), kElbowCut);
  rig.cycles(5, kElbowCut);
  EXPECT_EQ(rig.reports.size(), 0u);
}

TEST(LostJointTracker, ReadsABoundedNumberOfNoticesPerCycle) {
  TrackerRig rig;
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(rig.notices.try_send(JointManagerNotice{NoticeKind::joints_cleared, 0, 0, Errc::ok}));
  }
  rig.cycles(1, 0);
  EXPECT_EQ(rig.notices.size(), 10 - LostJointTracker::kMaxNoticesPerCycle);
}

}  // namespace
}  // namespace rescue::app
