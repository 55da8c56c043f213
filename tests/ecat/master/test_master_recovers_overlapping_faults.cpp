// Online recovery when faults overlap (issue 22), on the simulated robot in virtual time:
// - a drive with joints behind it switched off and on again: while it is off every slave behind it
//   vanishes; when it boots they return at once with their station addresses and configuration but
//   their SyncManager watchdogs expired (SAFE-OP, 0x001B), the drive itself blank (INIT, address 0).
//   All of them come back to OP while every other branch keeps every period;
// - a fault during another slave's recovery, a cut behind a slave that is recovering, a restore
//   during a power cycle, the same slave failing twice;
// - a recovery that cannot finish (a hung application) fails, is reported each time, retried from
//   the start after a growing hold-off, and never holds up another branch's recovery.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

constexpr int kBackWithinPeriods = 1000;  // the bound: every returned slave in OP within 1 s

MasterOptions recovery_options() {
  MasterOptions options = testing::fast_options();
  options.online_recovery = true;
  return options;
}

JointMask branches_of(JointMask joints) {
  JointMask mask = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) != 0) mask |= joints_of_branch(kJoints[j].branch);
  }
  return mask;
}

std::size_t position_of(const char* joint) { return slave_position_of_joint(joint_index_by_name(joint)); }
JointMask bit_of(const char* joint) { return joint_bit(joint_index_by_name(joint)); }
// The joint and every joint behind it (the slaves its loss takes along).
JointMask behind(const char* joint) {
  return drivers::joints_of_slaves(subtree_of(drivers::kRobotNetworkPlan, position_of(joint)));
}

// Runs the robot period by period, collecting the master's reports and the periods in which a
// joint of `untouched` (branches without a fault) missed its exchange.
struct Runner {
  SimulatedRobotRig& rig;
  JointMask untouched{kAllJoints};
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  int periods{0};
  int missed_untouched{0};
  JointMask lost{0};
  JointMask recovered{0};
  int failures_reported{0};
  int table_refusals_seen{0};

  drivers::JointCycleResult step() {
    const drivers::JointCycleResult r = rig.cycle(refs, fb);
    ++periods;
    if (!r.frame_received || (r.valid & untouched) != untouched) ++missed_untouched;
    LinkReport report;
    while (rig.bus.master().pop_report(report)) {
      const JointMask joints = drivers::joints_of_slaves(report.slaves);
      if (report.kind == LinkEventKind::lost || report.kind == LinkEventKind::not_operational) lost |= joints;
      if (report.kind == LinkEventKind::recovered) recovered |= joints;
      if (report.kind == LinkEventKind::recovery_failed) ++failures_reported;
    }
    return r;
  }
  void run(int n) {
    for (int i = 0; i < n; ++i) (void)step();
  }
  // The drive of `joint` off for `off_periods`, then on again.
  void power_off_on(const char* joint, int off_periods) {
    ASSERT_TRUE(rig.segment.set_power(slave_position_of_joint(joint_index_by_name(joint)), false, rig.clock.now()).ok());
    run(off_periods);
    ASSERT_TRUE(rig.segment.set_power(slave_position_of_joint(joint_index_by_name(joint)), true, rig.clock.now()).ok());
  }
  // Periods until every joint of `joints` is in the exchange again (valid), or -1.
  int until_valid(JointMask joints, int limit) {
    for (int i = 1; i <= limit; ++i) {
      if ((step().valid & joints) == joints && (rig.bus.master().recovering() & drivers::slaves_of_joints(joints)) == 0) return i;
    }
    return -1;
  }
};

std::unique_ptr<SimulatedRobotRig> robot_in_op() { return testing::simulated_robot_in_op(recovery_options()); }

void expect_all_in_op(SimulatedRobotRig& rig) {
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    EXPECT_EQ(rig.segment.esc(p).al_state(), reg::AlState::op) << kSlaves[p].name;
    EXPECT_EQ(rig.segment.esc(p).register_u16(reg::kStationAddress), kSlaves[p].station_address) << kSlaves[p].name;
  }
  EXPECT_EQ(rig.bus.master().recovering(), 0u);
  EXPECT_EQ(rig.bus.master().recovery_stats().table_refusals, 0u);
}

// Every joint back in the exchange within the bound, no period missed on the untouched branches,
// every slave in OP at its address, nothing left recovering.
void expect_all_back(Runner& run) {
  EXPECT_GT(run.until_valid(kAllJoints, kBackWithinPeriods), 0);
  EXPECT_EQ(run.missed_untouched, 0);
  run.run(20);
  expect_all_in_op(run.rig);
}

class PowerOffWithJointsBehind : public ::testing::TestWithParam<const char*> {};

TEST_P(PowerOffWithJointsBehind, EverySlaveBehindReturnsAsARealEscAndAllAreRecovered) {
  auto rig = robot_in_op();
  Runner run{*rig};
  const char* drive = GetParam();
  const std::size_t position = position_of(drive);
  const JointMask gone = behind(drive);
  ASSERT_GT(popcount(gone), 1) << drive << " has joints behind it";
  run.untouched = kAllJoints & ~branches_of(gone);

  ASSERT_TRUE(rig->segment.set_power(position, false, rig->clock.now()).ok());
  run.run(300);  // off for 300 ms: everything behind it vanished, their watchdogs expired
  EXPECT_EQ(run.lost & gone, gone) << "every joint behind it reported";
  EXPECT_EQ(run.lost & ~gone, 0u);

  ASSERT_TRUE(rig->segment.set_power(position, true, rig->clock.now()).ok());
  // As it boots: itself blank, those behind it back at once, addressed, in SAFE-OP by their watchdog.
  EXPECT_EQ(rig->segment.esc(position).al_state(), reg::AlState::init);
  EXPECT_EQ(rig->segment.esc(position).register_u16(reg::kStationAddress), 0);
  for (std::size_t p = position + 1; p < kSlaveCount; ++p) {
    if ((subtree_of(drivers::kRobotNetworkPlan, position) & slave_bit(p)) == 0) continue;
    EXPECT_EQ(rig->segment.esc(p).register_u16(reg::kStationAddress), kSlaves[p].station_address) << kSlaves[p].name;
    EXPECT_EQ(rig->segment.esc(p).register_u16(reg::kAlStatus), static_cast<std::uint16_t>(reg::AlState::safe_op) | reg::kAlErrorBit)
        << kSlaves[p].name;
    EXPECT_EQ(rig->segment.esc(p).register_u16(reg::kAlStatusCode), reg::al_code::kSyncManagerWatchdog) << kSlaves[p].name;
  }
  const int back = run.until_valid(gone, kBackWithinPeriods);
  ASSERT_GT(back, 0) << drive << ": " << to_string(rig->bus.master().recovery_state(position));
  EXPECT_EQ(run.recovered & gone, gone);
  EXPECT_EQ(run.missed_untouched, 0) << "other branches keep every period";
  run.run(20);
  expect_all_in_op(*rig);
  EXPECT_LE(rig->bus.master().recovery_stats().max_datagrams_per_cycle, recovery_options().recovery_datagrams_per_cycle);
  std::printf("power-off %s (%d joints behind it and itself): all back in OP %d periods after power-on\n", drive, popcount(gone), back);
}

INSTANTIATE_TEST_SUITE_P(Drives, PowerOffWithJointsBehind,
                         ::testing::Values("r_leg", "neck_pan", "l_leg", "r_shoulder_pitch", "l_elbow", "waist_yaw"));

TEST(MasterOverlappingFaults, EachDriveWithJointsBehindItPowerCycledInTurn) {
  auto rig = robot_in_op();
  Runner run{*rig};
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const char* drive = kJoints[j].name;
    const JointMask gone = behind(drive);
    run.untouched = kAllJoints & ~branches_of(gone);
    run.missed_untouched = 0;
    run.power_off_on(drive, 150);
    const int back = run.until_valid(gone, kBackWithinPeriods);
    ASSERT_GT(back, 0) << drive;
    EXPECT_EQ(run.missed_untouched, 0) << drive;
    std::printf("power-off/on %-17s (%d joints): back in %3d periods\n", drive, popcount(gone), back);
  }
  run.run(20);
  expect_all_in_op(*rig);
}

TEST(MasterOverlappingFaults, AFaultOnAnotherBranchDuringARecovery) {
  auto rig = robot_in_op();
  Runner run{*rig};
  run.untouched = kAllJoints & ~branches_of(behind("r_leg") | behind("waist_yaw"));
  run.power_off_on("r_leg", 150);
  run.run(15);  // r_leg and the tracks are being recovered
  ASSERT_NE(rig->bus.master().recovering(), 0u);
  ASSERT_TRUE(rig->segment.cut_link(position_of("waist_yaw")).ok());
  run.run(150);
  ASSERT_TRUE(rig->segment.restore_link(position_of("waist_yaw")).ok());
  expect_all_back(run);
}

TEST(MasterOverlappingFaults, ACutBehindASlaveThatIsRecovering) {
  auto rig = robot_in_op();
  Runner run{*rig};
  run.untouched = kAllJoints & ~branches_of(behind("r_leg"));
  run.power_off_on("r_leg", 150);
  run.run(10);
  ASSERT_NE(rig->bus.master().recovering() & slave_bit(position_of("r_leg")), 0u);
  ASSERT_TRUE(rig->segment.cut_link(position_of("r_track")).ok());
  // r_leg and l_track come back while r_track stays cut.
  EXPECT_GT(run.until_valid(bit_of("r_leg") | bit_of("l_track"), kBackWithinPeriods), 0);
  EXPECT_EQ(rig->bus.master().recovery_state(position_of("r_track")), RecoveryState::searching);
  ASSERT_TRUE(rig->segment.restore_link(position_of("r_track")).ok());
  expect_all_back(run);
}

TEST(MasterOverlappingFaults, ARestoreDuringAPowerCycle) {
  auto rig = robot_in_op();
  Runner run{*rig};
  run.untouched = kAllJoints & ~branches_of(behind("l_leg"));
  // The lower body's cable cut at l_leg; while it is cut, r_leg (behind the cut) loses its power;
  // the cable is restored while r_leg is still off, then r_leg is switched on.
  ASSERT_TRUE(rig->segment.cut_link(position_of("l_leg")).ok());
  run.run(100);
  ASSERT_TRUE(rig->segment.set_power(position_of("r_leg"), false, rig->clock.now()).ok());
  run.run(100);
  ASSERT_TRUE(rig->segment.restore_link(position_of("l_leg")).ok());
  EXPECT_GT(run.until_valid(bit_of("l_leg"), kBackWithinPeriods), 0) << "l_leg back while r_leg is off";
  run.run(100);
  ASSERT_TRUE(rig->segment.set_power(position_of("r_leg"), true, rig->clock.now()).ok());
  expect_all_back(run);
}

TEST(MasterOverlappingFaults, TheSameSlaveFailingTwice) {
  auto rig = robot_in_op();
  Runner run{*rig};
  run.untouched = kAllJoints & ~branches_of(behind("neck_pan"));
  // Power lost again in the middle of its recovery, then again once it is back.
  run.power_off_on("neck_pan", 150);
  run.run(12);
  ASSERT_NE(rig->bus.master().recovering() & slave_bit(position_of("neck_pan")), 0u);
  run.power_off_on("neck_pan", 150);
  EXPECT_GT(run.until_valid(kAllJoints, kBackWithinPeriods), 0);
  ASSERT_TRUE(rig->segment.power_cycle(position_of("neck_pan"), rig->clock.now()).ok());
  run.run(5);
  EXPECT_GT(run.until_valid(kAllJoints, kBackWithinPeriods), 0);
  EXPECT_EQ(run.missed_untouched, 0);
  EXPECT_GE(rig->bus.master().recovery_stats().recovered, 3u);  // neck_pan + neck_tilt, then neck_pan
  run.run(20);
  expect_all_in_op(*rig);
}

TEST(MasterOverlappingFaults, ARecoveryThatCannotFinishIsRetriedWithBackOffAndBlocksNoOtherBranch) {
  auto rig = robot_in_op();
  Runner run{*rig};
  const std::size_t hand = position_of("r_hand");
  // r_hand's power is cycled and its application hangs: AL control is never served, so its
  // recovery cannot get past Resetting.
  ASSERT_TRUE(rig->segment.power_cycle(hand, rig->clock.now()).ok());
  ASSERT_TRUE(rig->segment.freeze(hand, true).ok());
  run.untouched = kAllJoints & ~branches_of(bit_of("r_hand") | behind("l_shoulder_pitch"));
  run.run(1500);
  EXPECT_GE(run.failures_reported, 1);
  EXPECT_GE(rig->bus.master().recovery_failures(hand), 1);
  // Meanwhile the left arm is cut and restored: it recovers as if nothing else were going on.
  ASSERT_TRUE(rig->segment.cut_link(position_of("l_shoulder_pitch")).ok());
  run.run(150);
  ASSERT_TRUE(rig->segment.restore_link(position_of("l_shoulder_pitch")).ok());
  EXPECT_GT(run.until_valid(behind("l_shoulder_pitch"), kBackWithinPeriods), 0);
  // Still failing: each failure reported, the hold-off doubling (1, 2, 4, 8 s at most).
  run.run(12000);
  const int failures = run.failures_reported;
  EXPECT_GE(failures, 3);
  EXPECT_LE(failures, 6) << "hold-off grows";
  EXPECT_GE(rig->bus.master().recovery_failures(hand), 3);
  std::printf("hung r_hand: %d failures reported in %d periods, %u in a row\n", failures, run.periods,
              static_cast<unsigned>(rig->bus.master().recovery_failures(hand)));
  // The application runs again: the next attempt recovers it.
  ASSERT_TRUE(rig->segment.freeze(hand, false).ok());
  EXPECT_GT(run.until_valid(kAllJoints, 10000), 0);
  EXPECT_EQ(rig->bus.master().recovery_failures(hand), 0);
  EXPECT_EQ(run.missed_untouched, 0);
  run.run(20);
  expect_all_in_op(*rig);
}

}  // namespace
}  // namespace rescue::ecat
