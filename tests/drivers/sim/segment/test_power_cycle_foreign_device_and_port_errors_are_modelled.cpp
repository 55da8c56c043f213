// The simulator models what online recovery and link diagnostics need: a power-cycled ESC loses its
// registers and station address and comes back in INIT with its SII unchanged; a foreign device
// answers with another product code; a replaced cable counts a lost link upstream; damage on one
// cable counts an invalid frame on that port and a forwarded RX error on every port the damaged
// frame reaches afterwards; each of these is reachable as a fault command.
#include <cstring>

#include "drivers/sim/segment/fault_command.hpp"
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

Status apply(Rig& rig, const char* text) {
  const auto command = parse_fault_command(text, std::strlen(text), rig.segment);
  if (!command.ok()) return command.error();
  return apply_fault_command(command.value(), rig.segment, rig.now);
}

std::uint16_t station_of(std::size_t position) { return static_cast<std::uint16_t>(kStationAddressBase + position); }

TEST(SimulatedPowerCycle, LosesRegistersAndAddressButKeepsItsSii) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  const std::uint16_t station = station_of(elbow);
  ASSERT_EQ(rig->write16(station, reg::fmmu(0), 0x1234), 1);
  ASSERT_EQ(rig->segment.esc(elbow).register_u16(reg::fmmu(0)), 0x1234);
  const std::uint16_t product_before = rig->segment.esc(elbow).register_u16(0);  // ESC type etc. unchanged too
  const std::uint8_t upstream_lost_before =
      rig->segment.esc(elbow - 1).register_u8(reg::kLostLinkCounter + rig->segment.slave(elbow).upstream_port);

  ASSERT_TRUE(apply(*rig, "power-cycle l_elbow").ok());
  EXPECT_EQ(rig->read(Command::FPRD, station, reg::kAlStatus, 2).wkc, 0) << "station address lost";
  const auto at_position = rig->read(Command::APRD, ecat::position_adp(static_cast<std::uint16_t>(elbow)), reg::kStationAddress, 2);
  ASSERT_EQ(at_position.wkc, 1);
  EXPECT_EQ(at_position.data[0] | (at_position.data[1] << 8), 0);
  EXPECT_EQ(rig->segment.esc(elbow).al_state(), reg::AlState::init);
  EXPECT_EQ(rig->segment.esc(elbow).register_u16(reg::fmmu(0)), 0) << "registers lost";
  EXPECT_EQ(rig->segment.esc(elbow).register_u16(0), product_before);
  EXPECT_EQ(rig->segment.esc(elbow - 1).register_u8(reg::kLostLinkCounter + rig->segment.slave(elbow).upstream_port),
            upstream_lost_before + 1);
  EXPECT_FALSE(rig->segment.esc(elbow).foreign_identity());
}

TEST(SimulatedForeignDevice, AnswersWithAnotherProductCodeUntilTheOriginalIsBack) {
  auto rig = Rig::robot();
  const std::size_t hand = slave_position_of_joint(joint_index_by_name("r_hand"));
  const auto product = [&] {
    rig->wait(hal::kNsPerMs);
    EXPECT_EQ(rig->write(Command::APWR, ecat::position_adp(static_cast<std::uint16_t>(hand)), reg::kSiiControl,
                         {0x00, 0x01, ecat::sii::kProductCode, 0x00, 0x00, 0x00})
                  .wkc,
              1);
    rig->wait(hal::kNsPerMs);
    const auto r = rig->read(Command::APRD, ecat::position_adp(static_cast<std::uint16_t>(hand)), reg::kSiiData, 4);
    return static_cast<std::uint32_t>(r.data[0] | (r.data[1] << 8) | (r.data[2] << 16) | (static_cast<std::uint32_t>(r.data[3]) << 24));
  };
  const std::uint32_t planned = product();
  ASSERT_TRUE(apply(*rig, "foreign r_hand").ok());
  EXPECT_NE(product(), planned);
  ASSERT_TRUE(apply(*rig, "original r_hand").ok());
  EXPECT_EQ(product(), planned);
}

TEST(SimulatedPortErrors, DamageOnOneCableCountsThereAndDownstream) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  for (std::size_t p = 0; p < rig->segment.slave_count(); ++p) {
    (void)rig->write(Command::FPWR, station_of(p), reg::kRxErrorCounter, std::vector<std::uint8_t>(reg::kErrorCountersLength, 0));
  }
  ASSERT_TRUE(apply(*rig, "corrupt-port l_elbow 0 3").ok());
  for (int i = 0; i < 5; ++i) (void)rig->read(Command::BRD, 0, reg::kType, 1);
  EXPECT_EQ(rig->segment.counters().lost_port_corruption, 3u);
  EXPECT_EQ(rig->segment.esc(elbow).register_u8(reg::kRxErrorCounter), 3);  // invalid frames on port 0
  // The next slave on the branch received the damaged frames on its port 0: forwarded errors.
  EXPECT_EQ(rig->segment.esc(elbow + 1).register_u8(reg::kForwardedRxErrorCounter), 3);
  EXPECT_EQ(rig->segment.esc(elbow - 1).register_u8(reg::kRxErrorCounter), 0) << "the cable in front is healthy";
  // The damaged frames return through the upstream slave's port 1: a forwarded error there.
  EXPECT_EQ(rig->segment.esc(elbow - 1).register_u8(reg::kForwardedRxErrorCounter + 1), 3);
  const auto back = rig->read(Command::BRD, 0, reg::kType, 1);
  EXPECT_TRUE(back.returned);
}

TEST(SimulatedReplacedCable, CountsALostLinkAndKeepsTheSlavesConfiguration) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  const std::size_t wrist = slave_position_of_joint(joint_index_by_name("r_wrist_yaw"));
  ASSERT_TRUE(apply(*rig, "replace-cable r_wrist_yaw").ok());
  EXPECT_EQ(rig->read16(station_of(wrist), reg::kStationAddress), station_of(wrist));
  EXPECT_EQ(rig->segment.esc(wrist).register_u8(reg::kLostLinkCounter), 1);
}

TEST(FaultCommandsForRecovery, ParseAndRefuseBadPorts) {
  auto rig = Rig::robot();
  const auto c = parse_fault_command("corrupt-port neck_pan 1 7", 25, rig->segment);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c.value().kind, FaultKind::corrupt_port);
  EXPECT_EQ(c.value().port, 1u);
  EXPECT_EQ(c.value().value, 7u);
  EXPECT_EQ(parse_fault_command("corrupt-port neck_pan 4 7", 25, rig->segment).error().code, Errc::out_of_range);
  EXPECT_EQ(parse_fault_command("corrupt-port neck_pan 1", 23, rig->segment).error().code, Errc::invalid_argument);
  EXPECT_TRUE(parse_fault_command("power-cycle 5", 13, rig->segment).ok());
}

}  // namespace
}  // namespace rescue::drivers::testing
