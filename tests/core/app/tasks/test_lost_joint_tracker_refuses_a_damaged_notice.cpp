// A joint manager's notice is a record of the shared segment: an unknown kind or a joint beyond the
// robot is damage (a stray write, a bit flip), refused and counted. Read as it is, an unknown kind
// was taken as an operator's clear and the handler commanded its confirmed lost joints again.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "core/app/tasks/lost_joint_tracker.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

using testing::FakeQueue;

const JointMask kElbowCut = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));

struct TrackerRig {
  TrackerRig() : tracker(reports, notices, 0) {}
  void cycles(int n, JointMask out) {
    for (int i = 0; i < n; ++i) {
      ++cycle;
      tracker.on_cycle(cycle, static_cast<hal::Nanoseconds>(cycle) * hal::kNsPerMs, out);
    }
  }
  // The elbow branch lost, reported and confirmed by the joint manager.
  void confirm_elbow_loss() {
    cycles(1, kElbowCut);
    LostJointsReport report;
    ASSERT_TRUE(reports.try_receive(report));
    ASSERT_TRUE(notices.try_send(JointManagerNotice{NoticeKind::lost_joints_recorded, kElbowCut, cycle, Errc::ok}));
    cycles(1, 0);
    ASSERT_EQ(tracker.confirmed(), kElbowCut);
  }
  FakeQueue<LostJointsReport> reports;
  FakeQueue<JointManagerNotice> notices;
  LostJointTracker tracker;
  std::uint64_t cycle{0};
};

JointManagerNotice with_kind_byte(std::uint8_t byte, JointMask joints) {
  JointManagerNotice n{NoticeKind::joints_cleared, joints, 0, Errc::ok};
  std::memcpy(&n.kind, &byte, sizeof byte);  // as a stray write leaves it in the segment
  return n;
}

TEST(LostJointTracker, ANoticeOfAnUnknownKindIsRefusedAndCountedAndUnlatchesNothing) {
  TrackerRig rig;
  rig.confirm_elbow_loss();
  ASSERT_TRUE(rig.notices.try_send(with_kind_byte(0x5A, kElbowCut)));
  rig.cycles(1, 0);
  EXPECT_EQ(rig.tracker.confirmed(), kElbowCut);
  EXPECT_EQ(rig.tracker.excluded(), kElbowCut);
  EXPECT_EQ(rig.tracker.damaged_notices(), 1u);
}

TEST(LostJointTracker, ANoticeNamingAJointBeyondTheRobotIsRefusedWhole) {
  TrackerRig rig;
  rig.confirm_elbow_loss();
  const JointMask beyond = JointMask{1} << kJointCount;
  ASSERT_TRUE(rig.notices.try_send(JointManagerNotice{NoticeKind::joints_cleared, kElbowCut | beyond, 0, Errc::ok}));
  rig.cycles(1, 0);
  EXPECT_EQ(rig.tracker.confirmed(), kElbowCut);
  EXPECT_EQ(rig.tracker.damaged_notices(), 1u);
  // A whole notice after it is taken as before.
  ASSERT_TRUE(rig.notices.try_send(JointManagerNotice{NoticeKind::joints_cleared, kElbowCut, 0, Errc::ok}));
  rig.cycles(1, 0);
  EXPECT_EQ(rig.tracker.confirmed(), 0u);
  EXPECT_EQ(rig.tracker.damaged_notices(), 1u);
}

}  // namespace
}  // namespace rescue::app
