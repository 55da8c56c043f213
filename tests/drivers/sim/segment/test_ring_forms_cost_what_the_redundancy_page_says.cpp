// docs/redundancy.md, form 2: the classic ring on the paper's tree (l_hand's free port 1 cabled back
// to the master's ring port) covers only the cables on the path from the master to l_hand. A cut
// there loses nothing (main + ring reach all 23 slaves); a cut elsewhere loses what is behind it, as
// in the tree. Form 4 (a loop per branch through the junctions' spare ports): the processing order is
// the tree's; a single cut inside a loop costs nothing even for the main port's frame alone; any
// single cut loses nothing with both ports; two cuts in different loops lose nothing, two in the same
// loop the slaves between them and the loops hanging off those. Form 3 (the robot's ring
// configuration) is test_robot_ring_loses_no_slave_to_any_single_cut.
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

// Form 4: a:0 master; a:3 -> b:0; b:3 -> right arm -> r_hand:1 -> b:1 (loop 0); b:2 -> legs ->
// r_track:1 -> a:1 (loop 1); a:2 -> waist, neck -> l_shoulder_pitch .. l_hand -> l_hand:1 -> ring.
std::unique_ptr<Rig> loop_per_branch() {
  auto rig = Rig::robot();  // the tree's devices, rebuilt below with form 4's cables
  std::array<SlaveDevice*, kSlaveCount> devices{};
  std::size_t junction = 0;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    devices[p] = kSlaves[p].kind == SlaveKind::junction ? static_cast<SlaveDevice*>(rig->junctions[junction++].get()) : rig->by_position[p];
  }
  std::array<SegmentSlave, kSlaveCount> slaves{};
  EXPECT_TRUE(describe_robot_segment(Span<SlaveDevice* const>(devices), RobotSegmentOptions{}, Span<SegmentSlave>(slaves)).ok());
  const auto at = [](const char* joint) { return slave_position_of_joint(joint_index_by_name(joint)); };
  slaves[at("r_shoulder_pitch")].upstream_port = 3;  // junction_b:3
  slaves[at("waist_yaw")].upstream_port = 2;         // junction_a:2
  slaves[at("l_shoulder_pitch")].upstream = static_cast<std::uint8_t>(at("neck_tilt"));
  slaves[at("l_shoulder_pitch")].upstream_port = 1;
  const std::array<LoopCable, 2> loops{{
      {static_cast<std::uint8_t>(at("r_hand")), 1, 1, 1, kPhyPairDelayNs + 8},
      {static_cast<std::uint8_t>(at("r_track")), 1, 0, 1, kPhyPairDelayNs + 8},
  }};
  EXPECT_TRUE(rig->segment.build_ring(Span<const SegmentSlave>(slaves), robot_ring_cable(), 0, Span<const LoopCable>(loops)).ok());
  return rig;
}

int main_alone(Rig& rig) {
  const auto r = rig.read(Command::BRD, 0, reg::kType, 1);
  return r.returned ? r.wkc : 0;
}

// Cables of form 4: 0..22 into each slave's port 0, 23 the ring cable, 24 and 25 the two loop cables.
void set_cut(Rig& rig, std::size_t cable, bool cut) {
  Status st;
  if (cable < kSlaveCount) {
    st = cut ? rig.segment.cut_link(cable) : rig.segment.restore_link(cable);
  } else if (cable == kSlaveCount) {
    st = cut ? rig.segment.cut_ring_cable() : rig.segment.restore_ring_cable();
  } else {
    st = rig.segment.set_loop_cable_cut(cable - kSlaveCount - 1, cut);
  }
  ASSERT_TRUE(st.ok()) << cable;
}
constexpr std::size_t kFormFourCables = kSlaveCount + 3;

TEST(RingForms, LoopPerBranchKeepsTheTreesOrderAndSurvivesAnySingleCut) {
  auto rig = loop_per_branch();
  ASSERT_EQ(rig->segment.slave_count(), kSlaveCount);
  EXPECT_EQ(main_alone(*rig), kSlaveCount);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::ring);
  for (std::size_t cable = 0; cable < kFormFourCables; ++cable) {
    set_cut(*rig, cable, true);
    EXPECT_EQ(reached(*rig), kSlaveCount) << "cable " << cable;
    set_cut(*rig, cable, false);
  }
  // Inside a loop (the right arm's, the legs', between the junctions, a loop cable): main alone.
  for (const std::size_t cable : {std::size_t{1}, slave_position_of_joint(joint_index_by_name("r_elbow")),
                                  slave_position_of_joint(joint_index_by_name("r_leg")), kSlaveCount + 1, kSlaveCount + 2}) {
    set_cut(*rig, cable, true);
    EXPECT_EQ(main_alone(*rig), kSlaveCount) << "cable " << cable;
    EXPECT_EQ(rig->last_outcome.port, MasterPort::ring) << "the outer ring stays closed, cable " << cable;
    set_cut(*rig, cable, false);
  }
}

TEST(RingForms, LoopPerBranchLosesSlavesOnlyToTwoCutsInOneLoop) {
  auto rig = loop_per_branch();
  const auto at = [](const char* joint) { return slave_position_of_joint(joint_index_by_name(joint)); };
  struct Case {
    std::size_t first;
    std::size_t second;
    int lost;
  };
  const std::array<Case, 5> cases{{
      {at("r_elbow"), at("l_track"), 0},                  // two loops
      {at("r_elbow"), at("l_elbow"), 0},                  // the right arm's loop and the outer one
      {at("r_shoulder_roll"), at("r_wrist_yaw"), 3},      // r_shoulder_roll .. r_elbow
      {at("neck_pan"), at("l_elbow"), 5},                 // neck_pan .. l_shoulder_yaw
      {1, kSlaveCount + 2, 12},                           // the legs' loop at both junctions: b, arm and legs
  }};
  for (const Case& c : cases) {
    set_cut(*rig, c.first, true);
    set_cut(*rig, c.second, true);
    EXPECT_EQ(reached(*rig), static_cast<int>(kSlaveCount) - c.lost) << "cuts " << c.first << " and " << c.second;
    set_cut(*rig, c.first, false);
    set_cut(*rig, c.second, false);
    EXPECT_EQ(main_alone(*rig), kSlaveCount);
  }
}

TEST(RingForms, ALoopCableOntoATakenPortIsRefused) {
  auto rig = Rig::robot();
  std::array<SegmentSlave, kSlaveCount> slaves{};
  for (std::size_t p = 0; p < kSlaveCount; ++p) slaves[p] = rig->segment.slave(p);
  // junction_b:3 is free in the tree; l_hand:1 is where the ring cable ends.
  const std::array<LoopCable, 1> onto_the_ring_port{{{1, 3, kRingReturnSlave, kRingReturnPort, kPhyPairDelayNs}}};
  const Status st = rig->segment.build_ring(Span<const SegmentSlave>(slaves), robot_ring_cable(), 0, Span<const LoopCable>(onto_the_ring_port));
  ASSERT_FALSE(st.ok());
  EXPECT_STREQ(st.error().what, "ring cable onto a port already cabled");
}

}  // namespace
}  // namespace rescue::drivers::testing
