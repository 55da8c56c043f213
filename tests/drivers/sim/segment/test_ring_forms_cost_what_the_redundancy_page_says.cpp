// docs/redundancy.md, form 2: the classic ring on the paper's tree (l_hand's free port 1 cabled back
// to the master's ring port) covers only the cables on the path from the master to l_hand. A cut
// there loses nothing (main + ring reach all 23 slaves); a cut elsewhere loses what is behind it, as
// in the tree. Form 3 (the robot's ring configuration) is test_robot_ring_loses_no_slave_to_any_single_cut.
#include "core/robot/robot_ring.hpp"
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

int reached(Rig& rig) {
  int total = 0;
  for (const MasterPort from : {MasterPort::main, MasterPort::ring}) {
    rig.send_port = from;
    const auto r = rig.read(Command::BRD, 0, reg::kType, 1);
    total += r.returned ? r.wkc : 0;
  }
  rig.send_port = MasterPort::main;
  return total;
}

std::unique_ptr<Rig> classic_ring_on_the_tree() {
  const RingCable ring = robot_ring_cable();  // l_hand:1, free in the tree
  return Rig::robot(RobotSegmentOptions{}, &ring);
}

TEST(RingForms, ClassicRingOnTheTreeCoversOnlyThePathToTheLastSlave) {
  auto rig = classic_ring_on_the_tree();
  ASSERT_TRUE(rig->segment.has_ring());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::ring);

  // On the path: the master cable, the cables into l_shoulder_pitch .. l_hand, the ring cable.
  int on_the_path = 0;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    ASSERT_TRUE(rig->segment.cut_link(p).ok());
    const int answered = reached(*rig);
    ASSERT_TRUE(rig->segment.restore_link(p).ok());
    const bool path = p == 0 || p >= slave_position_of_joint(joint_index_by_name("l_shoulder_pitch"));
    if (path) {
      ++on_the_path;
      EXPECT_EQ(answered, kSlaveCount) << "cut on the path at " << kSlaves[p].name;
    } else {
      EXPECT_LT(answered, kSlaveCount) << "cut off the path at " << kSlaves[p].name;
    }
  }
  ASSERT_TRUE(rig->segment.cut_ring_cable().ok());
  EXPECT_EQ(reached(*rig), kSlaveCount);
  ASSERT_TRUE(rig->segment.restore_ring_cable().ok());
  EXPECT_EQ(on_the_path + 1, 9) << "9 cables lie on the ring";

  // The docs' two examples: r_elbow (4 behind it: r_elbow .. r_hand) and l_elbow (none).
  ASSERT_TRUE(rig->segment.cut_link(slave_position_of_joint(joint_index_by_name("r_elbow"))).ok());
  EXPECT_EQ(reached(*rig), kSlaveCount - 4);
  ASSERT_TRUE(rig->segment.restore_link(slave_position_of_joint(joint_index_by_name("r_elbow"))).ok());
  ASSERT_TRUE(rig->segment.cut_link(slave_position_of_joint(joint_index_by_name("l_elbow"))).ok());
  EXPECT_EQ(reached(*rig), kSlaveCount);
}

}  // namespace
}  // namespace rescue::drivers::testing
