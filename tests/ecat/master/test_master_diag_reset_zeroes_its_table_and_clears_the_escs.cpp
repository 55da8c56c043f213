// Master::reset_diagnostics (ctl diag --reset, docs/master.md "Resetting the counters") on the
// simulated robot: the master's table of the reset slaves is zeroed at once (counters and warnings,
// current and earlier), and their ESC error counters are cleared by a write in the next cyclic frame
// (a BWR for many slaves, an FPWR for one), so errors counted by an ESC before the reset but not yet
// read are never counted after it; other slaves keep their counts; new damage counts again.
#include <gtest/gtest.h>

#include <memory>

#include "ecat/codec/registers.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

void run(SimulatedRobotRig& rig, int n) { rig.idle_cycles(n); }

SlaveMask all_slaves() { return (SlaveMask{1} << kSlaveCount) - 1; }

TEST(MasterDiagReset, ErrorsAnEscCountedBeforeTheResetAreNeverCountedAfterIt) {
  auto rig = testing::simulated_robot_in_op();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(rig->segment.corrupt_port(elbow, 0, 5).ok());
  run(*rig, 8);  // the damaged frames passed; the round robin has not read l_elbow yet
  const LinkDiagnostics& d = rig->bus.master().diagnostics();
  ASSERT_EQ(rig->segment.esc(elbow).register_u8(reg::kRxErrorCounter), 5) << "the ESC counted them";
  ASSERT_EQ(d.counters(elbow).ports[0].invalid_frames, 0u) << "not read yet";
  rig->bus.master().reset_diagnostics(all_slaves());
  EXPECT_NE(rig->bus.master().diagnostics_clear_pending(), 0u);
  run(*rig, 1);
  EXPECT_EQ(rig->bus.master().diagnostics_clear_pending(), 0u) << "the write was answered";
  EXPECT_EQ(rig->segment.esc(elbow).register_u8(reg::kRxErrorCounter), 0) << "cleared by the master's write";
  EXPECT_EQ(rig->segment.esc(elbow + 1).register_u8(reg::kForwardedRxErrorCounter), 0);
  run(*rig, 1000);  // every slave read several times since
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    for (const PortCounters& port : d.counters(p).ports) {
      EXPECT_EQ(port.invalid_frames + port.rx_errors + port.forwarded_errors + port.lost_links, 0u) << kSlaves[p].name;
    }
    EXPECT_GE(d.counters(p).reads, 3u) << kSlaves[p].name;
  }
}

TEST(MasterDiagReset, OneSlaveIsZeroedAloneAndNewDamageCountsAgain) {
  auto rig = testing::simulated_robot_in_op();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(rig->segment.corrupt_port(elbow, 0, 5).ok());
  run(*rig, 1000);
  const LinkDiagnostics& d = rig->bus.master().diagnostics();
  ASSERT_EQ(d.counters(elbow).ports[0].invalid_frames, 5u);
  ASSERT_TRUE(d.ever_warned(elbow, 0));
  const std::uint64_t resets = d.resets();
  rig->bus.master().reset_diagnostics(slave_bit(elbow));
  EXPECT_EQ(d.resets(), resets + 1) << "a new table to publish";
  EXPECT_EQ(d.counters(elbow).ports[0].invalid_frames, 0u) << "zeroed at once";
  EXPECT_EQ(d.counters(elbow).reads, 0u);
  EXPECT_FALSE(d.warned(elbow, 0));
  EXPECT_FALSE(d.ever_warned(elbow, 0)) << "the earlier warning goes too";
  EXPECT_EQ(d.counters(elbow + 1).ports[0].forwarded_errors, 5u) << "another slave keeps its counts";
  run(*rig, 500);
  EXPECT_EQ(d.counters(elbow).ports[0].invalid_frames, 0u);
  ASSERT_TRUE(rig->segment.corrupt_port(elbow, 0, 3).ok());
  run(*rig, 1000);
  EXPECT_EQ(d.counters(elbow).ports[0].invalid_frames, 3u) << "the cable is still bad: it counts again";
  EXPECT_EQ(d.counters(elbow + 1).ports[0].forwarded_errors, 8u);
}

}  // namespace
}  // namespace rescue::ecat
