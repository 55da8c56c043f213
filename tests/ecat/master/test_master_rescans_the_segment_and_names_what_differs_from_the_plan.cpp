// Master::request_rescan (ctl rescan, docs/master.md "Rescan") on the simulated robot in OP: the
// segment is identified again in the cyclic frames (each device's SII by auto-increment position)
// while the slaves keep exchanging process data: every device reads as bring-up read it and nothing
// differs from the plan, no slave leaves the exchange; with a cable cut (neck_tilt, the torso's last
// slave, lost), the devices behind it in the frame are still placed right and neck_tilt alone is
// missing; one rescan at a time, none before OP.
#include <gtest/gtest.h>

#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;
using Refusal = RescanService::Refusal;

bool run_until_done(SimulatedRobotRig& rig, int limit) {
  for (int i = 0; i < limit; ++i) {
    rig.idle_cycles(1);
    if (rig.bus.master().take_rescan()) return true;
  }
  return false;
}

TEST(MasterRescan, EveryDeviceReadsAsAtBringUpAndNothingDiffersNorLeavesTheExchange) {
  auto rig = testing::simulated_robot_in_op();
  Master& master = rig->bus.master();
  const SlaveMask before = master.monitor().in_exchange();
  ASSERT_EQ(master.request_rescan(), Refusal::none);
  EXPECT_EQ(master.request_rescan(), Refusal::busy) << "one at a time";
  ASSERT_TRUE(run_until_done(*rig, 200));
  const RescanService& scan = master.rescan();
  EXPECT_EQ(scan.status(), RescanStatus::ok);
  EXPECT_EQ(scan.counted(), kSlaveCount);
  ASSERT_EQ(scan.found().size(), kSlaveCount);
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    const FoundSlave* at_bring_up = master.identity(p);
    ASSERT_NE(at_bring_up, nullptr) << p;
    EXPECT_EQ(scan.found()[p].vendor_id, at_bring_up->vendor_id) << p;
    EXPECT_EQ(scan.found()[p].product_code, at_bring_up->product_code) << p;
    EXPECT_EQ(scan.found()[p].revision, at_bring_up->revision) << p;
    EXPECT_EQ(scan.found()[p].serial_number, at_bring_up->serial_number) << p;
    EXPECT_EQ(scan.match().slot_of_found[p], p);
  }
  EXPECT_EQ(scan.match().differences.size(), 0U);
  EXPECT_EQ(master.monitor().in_exchange(), before) << "no slave disturbed";
  EXPECT_EQ(master.monitor().lost(), 0U);
  EXPECT_FALSE(master.take_rescan()) << "taken once";
}

TEST(MasterRescan, ACutCableLeavesItsSlaveMissingAndTheOthersInTheirPlaces) {
  auto rig = testing::simulated_robot_in_op();
  Master& master = rig->bus.master();
  const std::size_t neck = slave_position_of_joint(joint_index_by_name("neck_tilt"));
  ASSERT_TRUE(rig->segment.cut_link(neck).ok());
  rig->idle_cycles(50);
  ASSERT_NE(master.monitor().lost() & slave_bit(neck), 0U) << "confirmed lost";
  ASSERT_EQ(master.request_rescan(), Refusal::none);
  ASSERT_TRUE(run_until_done(*rig, 200));
  const RescanService& scan = master.rescan();
  ASSERT_EQ(scan.status(), RescanStatus::ok);
  EXPECT_EQ(scan.counted(), kSlaveCount - 1);
  ASSERT_EQ(scan.match().differences.size(), 1U);
  EXPECT_EQ(scan.match().differences[0].kind, DifferenceKind::missing);
  EXPECT_EQ(scan.match().differences[0].planned, neck);
  // The device after neck_tilt in frame order answers as its own slave, one place earlier.
  EXPECT_EQ(scan.match().slot_of_found[neck], neck + 1);
}

}  // namespace
}  // namespace rescue::ecat
