// Fault commands as text (for a running simulator): each command parses to what it says, names
// and positions both find slaves, malformed lines are refused with a reason, applying one changes
// the segment.
#include <cstring>

#include "drivers/sim/segment/fault_command.hpp"
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

Result<FaultCommand> parse(const SimulatedSegment& segment, const char* text) {
  return parse_fault_command(text, std::strlen(text), segment);
}

TEST(FaultCommands, EachCommandParses) {
  auto rig = Rig::robot();
  const auto& s = rig->segment;
  auto c = parse(s, "cut l_elbow");
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c.value().kind, FaultKind::cut);
  EXPECT_EQ(c.value().position, slave_position_of_joint(joint_index_by_name("l_elbow")));
  EXPECT_EQ(parse(s, "restore 19").value().position, 19u);
  EXPECT_EQ(parse(s, "  freeze   junction_b \n").value().kind, FaultKind::freeze);
  EXPECT_EQ(parse(s, "thaw junction_b").value().position, 1u);
  EXPECT_EQ(parse(s, "power-off r_hand").value().kind, FaultKind::power_off);
  EXPECT_EQ(parse(s, "power-on r_hand").value().kind, FaultKind::power_on);
  EXPECT_EQ(parse(s, "drop 3").value().value, 3u);
  EXPECT_EQ(parse(s, "corrupt 0x10").value().value, 16u);
  const auto fault = parse(s, "drive-fault neck_pan 0x7305");
  ASSERT_TRUE(fault.ok());
  EXPECT_EQ(fault.value().kind, FaultKind::drive_fault);
  EXPECT_EQ(fault.value().value, 0x7305u);
  const auto drop = parse(s, "safe-op l_elbow 0x001A");
  ASSERT_TRUE(drop.ok());
  EXPECT_EQ(drop.value().kind, FaultKind::safe_op);
  EXPECT_EQ(drop.value().value, 0x001Au);
  EXPECT_EQ(parse(s, "half-mapped l_elbow").value().kind, FaultKind::half_mapped);
  EXPECT_EQ(parse(s, "foreign-mapping l_elbow").value().kind, FaultKind::foreign_mapping);
  EXPECT_EQ(parse(s, "extra-slave").value().kind, FaultKind::extra_slave);
  const auto refuse = parse(s, "refuse r_elbow safe-op 0x001D");
  ASSERT_TRUE(refuse.ok());
  EXPECT_EQ(refuse.value().kind, FaultKind::refuse);
  EXPECT_EQ(refuse.value().state, AlState::safe_op);
  EXPECT_EQ(refuse.value().value, 0x001Du);
  EXPECT_FALSE(parse(s, "refuse r_elbow boot 0x001D").ok());
  EXPECT_FALSE(parse(s, "refuse r_elbow safe-op").ok());
}

TEST(FaultCommands, MalformedLinesAreRefusedWithAReason) {
  auto rig = Rig::robot();
  const auto& s = rig->segment;
  EXPECT_EQ(parse(s, "").error().code, Errc::invalid_argument);
  EXPECT_EQ(parse(s, "explode l_elbow").error().code, Errc::not_found);
  EXPECT_EQ(parse(s, "cut nobody").error().code, Errc::not_found);
  EXPECT_EQ(parse(s, "cut 23").error().code, Errc::not_found);  // positions 0..22
  EXPECT_EQ(parse(s, "cut").error().code, Errc::invalid_argument);
  EXPECT_EQ(parse(s, "cut l_elbow now").error().code, Errc::invalid_argument);
  EXPECT_EQ(parse(s, "drop many").error().code, Errc::invalid_argument);
  EXPECT_EQ(parse(s, "drop 99999999999").error().code, Errc::invalid_argument);
  EXPECT_EQ(parse(s, "drive-fault l_leg 0x10000").error().code, Errc::out_of_range);
  EXPECT_EQ(parse(s, "safe-op l_leg 0x10000").error().code, Errc::out_of_range);
  EXPECT_EQ(parse(s, "safe-op l_leg").error().code, Errc::invalid_argument);
  EXPECT_EQ(parse(s, "a b c d e").error().code, Errc::malformed);
  const char not_terminated[] = {'c', 'u', 't', ' ', '3'};
  EXPECT_TRUE(parse_fault_command(not_terminated, sizeof(not_terminated), s).ok());
}

TEST(FaultCommands, ApplyingACutTakesTheBranchTailAway) {
  auto rig = Rig::robot();
  const auto c = parse(rig->segment, "cut r_wrist_yaw");
  ASSERT_TRUE(c.ok());
  ASSERT_TRUE(apply_fault_command(c.value(), rig->segment, rig->now).ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount - 3);
  ASSERT_TRUE(apply_fault_command(parse(rig->segment, "restore r_wrist_yaw").value(), rig->segment, rig->now).ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount);
  ASSERT_TRUE(apply_fault_command(parse(rig->segment, "drop 1").value(), rig->segment, rig->now).ok());
  EXPECT_FALSE(rig->read(Command::BRD, 0, reg::kType, 1).returned);
}

// On the ring configuration every cable takes the cable commands: the slaves' (by name) and the
// ring-return cable ("ring"); power-cycle works on every slave. On a tree "ring" is refused.
TEST(FaultCommands, RingCableCommandsWorkOnEveryCableOfTheRing) {
  RobotSegmentOptions options;
  options.ring = true;
  auto rig = Rig::robot(options);
  const auto apply = [&](const char* text) {
    const auto c = parse(rig->segment, text);
    return c.ok() ? apply_fault_command(c.value(), rig->segment, rig->now) : Status(c.error());
  };
  const auto ring_wkc = [&] {
    rig->send_port = MasterPort::ring;
    const auto r = rig->read(Command::BRD, 0, reg::kType, 1);
    rig->send_port = MasterPort::main;
    return r.returned ? static_cast<int>(r.wkc) : -1;
  };
  ASSERT_TRUE(apply("cut ring").ok());
  EXPECT_TRUE(rig->segment.ring_cable_cut());
  EXPECT_EQ(ring_wkc(), -1);  // the ring port's cable is cut: nothing comes back on it
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::main);
  ASSERT_TRUE(apply("restore ring").ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::ring);
  ASSERT_TRUE(apply("replace-cable ring").ok());
  EXPECT_FALSE(rig->segment.ring_cable_cut());
  EXPECT_EQ(rig->segment.esc(kSlaveCount - 1).register_u32(reg::kLostLinkCounter) >> 8 & 0xFFU, 2u);  // port 1 lost its link twice (cut, replaced)

  ASSERT_TRUE(apply("cut l_elbow").ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc + ring_wkc(), kSlaveCount);
  ASSERT_TRUE(apply("restore l_elbow").ok());
  ASSERT_TRUE(apply("power-cycle l_hand").ok());  // the slave the ring cable ends at
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, kSlaveCount);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::ring);

  EXPECT_STREQ(parse(rig->segment, "freeze ring").error().what, "the ring cable takes cut, restore and replace-cable only");
  auto tree = Rig::robot();
  EXPECT_STREQ(parse(tree->segment, "cut ring").error().what, "no ring cable: the segment is a tree");
}

}  // namespace
}  // namespace rescue::drivers::testing
