// Two devices on one station address (issue 35 item 10's unconfirmed guess for the 24.5 s recovery
// over veth: a device given a slave's address by a wrong guess while the slave's own device kept it;
// here r_wrist_pitch's device is given r_hand's address while both are cut off). Neither can be
// configured by that address: every FPRD/FPWR to it has working counter 2. Before, r_hand's recovery
// took that for silence, went round Resetting and Searching and failed (then again after each
// hold-off: 1, 2, 4, 8 s), and r_wrist_pitch, finding another slave's address at its place, stayed
// Searching. Now the address is withdrawn from both (FPWR 0x0010 = 0 at it) and each device
// is found blank at its own place and recovered. On the simulated robot in virtual time.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>

#include "ecat/codec/frame.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

constexpr int kBackWithinPeriods = 1000;  // the issue 22 bound: 1 s

MasterOptions recovery_options() {
  MasterOptions options = testing::fast_options();
  options.online_recovery = true;
  return options;
}

// What a stray write does (another master's, or a wrong guess): FPWR 0x0010 = `address` at `now`.
void give_address(drivers::Esc& esc, std::uint16_t now, std::uint16_t address) {
  FrameBuilder frame;
  const std::array<std::uint8_t, 2> value{static_cast<std::uint8_t>(address & 0xFF), static_cast<std::uint8_t>(address >> 8)};
  ASSERT_TRUE(frame.add(Command::FPWR, 0, make_address(now, reg::kStationAddress), 2, ConstByteSpan(value)).ok());
  const ConstByteSpan built = frame.finish();
  std::array<std::uint8_t, kMaxFrameSize> bytes{};
  std::copy(built.begin(), built.end(), bytes.begin());
  auto parsed = MutableFrameView::parse(ByteSpan(bytes.data(), built.size()));
  ASSERT_TRUE(parsed.ok());
  for (const MutableDatagramView d : parsed.value()) esc.process(d);
  ASSERT_EQ(esc.register_u16(reg::kStationAddress), address);
}

TEST(TwoDevicesOnOneStationAddress, AreSeparatedAndBothSlavesRecovered) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  const std::size_t hand = slave_position_of_joint(joint_index_by_name("r_hand"));
  const std::size_t wrist = slave_position_of_joint(joint_index_by_name("r_wrist_pitch"));
  // r_wrist_pitch's cable cut (it and r_hand vanish, keeping their addresses); meanwhile its
  // device is given r_hand's address (a stray write, or a wrong guess); the cable restored.
  ASSERT_TRUE(rig->segment.cut_link(wrist).ok());
  int seen = 0;
  while ((rig->bus.master().recovering() & (slave_bit(wrist) | slave_bit(hand))) != (slave_bit(wrist) | slave_bit(hand)) &&
         seen < kBackWithinPeriods) {
    (void)rig->cycle(refs, fb);
    ++seen;
  }
  ASSERT_LT(seen, kBackWithinPeriods) << "the cut is seen";
  give_address(rig->segment.esc(wrist), kSlaves[wrist].station_address, kSlaves[hand].station_address);
  ASSERT_TRUE(rig->segment.restore_link(wrist).ok());
  int back = -1;
  for (int k = 1; k <= kBackWithinPeriods && back < 0; ++k) {
    const drivers::JointCycleResult r = rig->cycle(refs, fb);
    if (r.frame_received && (r.valid & kAllJoints) == kAllJoints && rig->bus.master().recovering() == 0) back = k;
  }
  ASSERT_GT(back, 0) << "r_hand " << to_string(rig->bus.master().recovery_state(hand)) << ", r_wrist_pitch "
                     << to_string(rig->bus.master().recovery_state(wrist)) << ", failures reported "
                     << rig->bus.master().recovery_stats().failed << "; station addresses: r_wrist_pitch's device 0x" << std::hex
                     << rig->segment.esc(wrist).register_u16(reg::kStationAddress) << ", r_hand's 0x"
                     << rig->segment.esc(hand).register_u16(reg::kStationAddress);
  for (int k = 0; k < 20; ++k) (void)rig->cycle(refs, fb);
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    EXPECT_EQ(rig->segment.esc(p).al_state(), reg::AlState::op) << kSlaves[p].name;
    EXPECT_EQ(rig->segment.esc(p).register_u16(reg::kStationAddress), kSlaves[p].station_address) << kSlaves[p].name;
  }
  EXPECT_GE(rig->bus.master().recovery_stats().shared_addresses, 1u);
  EXPECT_EQ(rig->bus.master().recovery_stats().failed, 0u);
  EXPECT_EQ(rig->bus.master().recovery_stats().table_refusals, 0u);
  std::printf("two devices on r_hand's address: separated, every slave back in OP %d periods after the restore\n", back);
}

}  // namespace
}  // namespace rescue::ecat
