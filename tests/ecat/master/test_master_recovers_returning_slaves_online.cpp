// Online recovery on the simulated robot (virtual time): a power-cycled drive (registers and
// station address lost, back in INIT) and a reconnected branch are noticed from the cyclic
// traffic, configured again and brought back to OP while every other joint keeps every period;
// a device of another type in a joint's place is refused and never configured. The number of
// periods back to OP and the recovery's extra datagrams per period are printed (docs/master.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "drivers/cia402/cia402_enable.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

constexpr int kMaxPeriodsBackToOp = 400;  // documented bound (docs/master.md): measured well below

ecat::MasterOptions recovery_options() {
  ecat::MasterOptions options = testing::fast_options();
  options.online_recovery = true;
  return options;
}

std::unique_ptr<SimulatedRobotRig> robot_in_op() { return testing::simulated_robot_in_op(recovery_options()); }

// Joints on the branches of `joints`.
JointMask branches_of(JointMask joints) {
  JointMask mask = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) != 0) mask |= joints_of_branch(kJoints[j].branch);
  }
  return mask;
}

struct Outcome {
  int periods{-1};            // from the fault to the recovered report
  int missed_elsewhere{0};    // periods in which a joint of another branch was not valid
  int missed_same_branch{0};  // periods in which a joint of the branch, not concerned, was not valid
  JointMask recovered{0};
  JointMask refused{0};
  int periods_all_valid_after{0};
};

// Cycles until `concerned` are reported recovered (or refused), counting the periods in which any
// other joint missed its exchange.
Outcome run_until_back(SimulatedRobotRig& rig, JointMask concerned, int limit) {
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  Outcome o;
  LinkReport report;
  for (int i = 1; i <= limit; ++i) {
    const drivers::JointCycleResult r = rig.cycle(refs, fb);
    const JointMask others = kAllJoints & ~branches_of(concerned);
    const JointMask neighbours = branches_of(concerned) & ~concerned;
    if (!r.frame_received || (r.valid & others) != others) ++o.missed_elsewhere;
    if ((r.valid & neighbours) != neighbours) ++o.missed_same_branch;
    while (rig.bus.master().pop_report(report)) {
      if (report.kind == LinkEventKind::recovered) o.recovered |= drivers::joints_of_slaves(report.slaves);
      if (report.kind == LinkEventKind::recovery_refused) o.refused |= drivers::joints_of_slaves(report.slaves);
    }
    if ((o.recovered | o.refused) == concerned) {
      o.periods = i;
      break;
    }
  }
  for (int i = 0; i < 20; ++i) {
    if (rig.cycle(refs, fb).valid == kAllJoints) ++o.periods_all_valid_after;
  }
  return o;
}

TEST(MasterOnlineRecovery, APowerCycledDriveReturnsToOp) {
  auto rig = robot_in_op();
  const std::size_t elbow = joint_index_by_name("l_elbow");
  const std::size_t position = slave_position_of_joint(elbow);
  ASSERT_TRUE(rig->segment.power_cycle(position, rig->clock.now()).ok());
  const Outcome o = run_until_back(*rig, joint_bit(elbow), kMaxPeriodsBackToOp);
  ASSERT_GT(o.periods, 0) << "state " << to_string(rig->bus.master().recovery_state(position));
  EXPECT_EQ(o.recovered, joint_bit(elbow));
  EXPECT_EQ(o.missed_elsewhere, 0);
  EXPECT_EQ(o.periods_all_valid_after, 20);
  EXPECT_EQ(rig->segment.esc(position).al_state(), reg::AlState::op);
  EXPECT_EQ(rig->segment.esc(position).register_u16(reg::kStationAddress), drivers::kRobotNetworkPlan[position].station_address);
  EXPECT_LE(rig->bus.master().recovery_stats().max_datagrams_per_cycle, recovery_options().recovery_datagrams_per_cycle);
  EXPECT_EQ(rig->bus.master().recovery_stats().table_refusals, 0u);
  // Its clock is back on the others' time, SYNC0 in phase, and its drive can be enabled again.
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  for (int i = 0; i < 500; ++i) (void)rig->cycle(refs, fb);
  const Result<DcSnapshot> dc = rig->bus.master().read_dc_snapshot();
  ASSERT_TRUE(dc.ok());
  EXPECT_NE(dc.value().answered & slave_bit(position), 0u);
  EXPECT_LT(dc.value().difference_ns[position], 1000u) << "DC time difference of the recovered slave";
  const std::uint64_t latches = rig->segment.esc(position).output_latch_count();
  for (int i = 0; i < 10; ++i) (void)rig->cycle(refs, fb);
  EXPECT_GE(rig->segment.esc(position).output_latch_count(), latches + 9) << "SYNC0 latches its outputs again";
  refs[elbow].mode_of_operation = static_cast<std::int8_t>(ControlMode::cyclic_position);
  refs[elbow].target_position = fb.joints[elbow].position_actual;
  for (int i = 0; i < 100 && !drivers::is_enabled(fb.joints[elbow].statusword); ++i) {
    refs[elbow].controlword = drivers::controlword_towards_enabled(fb.joints[elbow].statusword, refs[elbow].controlword);
    (void)rig->cycle(refs, fb);
  }
  EXPECT_TRUE(drivers::is_enabled(fb.joints[elbow].statusword)) << std::hex << fb.joints[elbow].statusword << " cw "
                                                                 << refs[elbow].controlword << " err " << fb.joints[elbow].error_code;
  std::printf("power-cycle l_elbow: back in %d periods, %d periods missed by its branch's other joints, max %u extra datagrams per period\n",
              o.periods, o.missed_same_branch, rig->bus.master().recovery_stats().max_datagrams_per_cycle);
}

TEST(MasterOnlineRecovery, EachOfTheTwentyOneDrivesPowerCycledInTurnReturnsToOp) {
  auto rig = robot_in_op();
  int worst = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::size_t position = slave_position_of_joint(j);
    ASSERT_TRUE(rig->segment.power_cycle(position, rig->clock.now()).ok());
    const Outcome o = run_until_back(*rig, joint_bit(j), kMaxPeriodsBackToOp);
    ASSERT_GT(o.periods, 0) << kJoints[j].name << " state " << to_string(rig->bus.master().recovery_state(position));
    EXPECT_EQ(o.recovered, joint_bit(j)) << kJoints[j].name;
    EXPECT_EQ(o.missed_elsewhere, 0) << kJoints[j].name;
    EXPECT_EQ(o.periods_all_valid_after, 20) << kJoints[j].name;
    EXPECT_EQ(rig->segment.esc(position).al_state(), reg::AlState::op) << kJoints[j].name;
    std::printf("power-cycle %-17s back in %3d periods (branch neighbours missed %d)\n", kJoints[j].name, o.periods,
                o.missed_same_branch);
    worst = std::max(worst, o.periods);
  }
  const RecoveryStats& stats = rig->bus.master().recovery_stats();
  EXPECT_EQ(stats.recovered, kJointCount);
  EXPECT_EQ(stats.refused, 0u);
  EXPECT_EQ(stats.table_refusals, 0u);
  EXPECT_LE(stats.max_datagrams_per_cycle, recovery_options().recovery_datagrams_per_cycle);
  std::printf("power-cycle, 21 drives: worst %d periods, max %u extra datagrams per period\n", worst, stats.max_datagrams_per_cycle);
}

TEST(MasterOnlineRecovery, EachBranchCutAndRestoredReturnsToOp) {
  auto rig = robot_in_op();
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  for (std::size_t b = 0; b < kBranchCount; ++b) {
    std::size_t first = kJointCount;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if (static_cast<std::size_t>(kJoints[j].branch) == b && kJoints[j].order_on_branch == 0) first = j;
    }
    ASSERT_LT(first, kJointCount);
    const JointMask branch = joints_of_branch(static_cast<Branch>(b));
    const std::size_t position = slave_position_of_joint(first);
    ASSERT_TRUE(rig->segment.cut_link(position).ok());
    for (int i = 0; i < 300; ++i) (void)rig->cycle(refs, fb);  // lost; the drives' watchdogs expire
    ASSERT_TRUE(rig->segment.restore_link(position).ok());
    const Outcome o = run_until_back(*rig, branch, kMaxPeriodsBackToOp);
    ASSERT_GT(o.periods, 0) << to_string(static_cast<Branch>(b)) << " state "
                            << to_string(rig->bus.master().recovery_state(position));
    EXPECT_EQ(o.recovered, branch);
    EXPECT_EQ(o.missed_elsewhere, 0) << to_string(static_cast<Branch>(b));
    EXPECT_EQ(o.periods_all_valid_after, 20);
    std::printf("branch %-10s (%d joints) cut and restored: back in %3d periods\n", to_string(static_cast<Branch>(b)),
                popcount(branch), o.periods);
  }
  EXPECT_LE(rig->bus.master().recovery_stats().max_datagrams_per_cycle, recovery_options().recovery_datagrams_per_cycle);
  std::printf("branches: max %u extra datagrams per period\n", rig->bus.master().recovery_stats().max_datagrams_per_cycle);
}

TEST(MasterOnlineRecovery, AForeignDeviceInAJointsPlaceIsRefusedThenTheRightOneReturns) {
  auto rig = robot_in_op();
  const std::size_t hand = joint_index_by_name("r_hand");
  const std::size_t position = slave_position_of_joint(hand);
  ASSERT_TRUE(rig->segment.plug_device(position, true, rig->clock.now()).ok());
  const Outcome refused = run_until_back(*rig, joint_bit(hand), kMaxPeriodsBackToOp);
  ASSERT_GT(refused.periods, 0);
  EXPECT_EQ(refused.refused, joint_bit(hand));
  EXPECT_EQ(refused.recovered, 0u);
  EXPECT_EQ(refused.missed_elsewhere, 0);
  EXPECT_EQ(rig->bus.master().recovery_state(position), RecoveryState::refused);
  // Never configured: still in INIT, no SyncManager or FMMU written.
  EXPECT_EQ(rig->segment.esc(position).al_state(), reg::AlState::init);
  EXPECT_EQ(rig->segment.esc(position).register_u8(reg::fmmu(0) + reg::kFmmuActivate), 0);
  EXPECT_EQ(rig->segment.esc(position).register_u16(reg::sync_manager(2)), 0);
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  for (int i = 0; i < 200; ++i) EXPECT_EQ(rig->cycle(refs, fb).valid & joint_bit(hand), 0u);
  EXPECT_EQ(rig->bus.master().recovery_stats().refused, 1u) << "reported once";

  ASSERT_TRUE(rig->segment.plug_device(position, false, rig->clock.now()).ok());
  const Outcome back = run_until_back(*rig, joint_bit(hand), kMaxPeriodsBackToOp);
  ASSERT_GT(back.periods, 0);
  EXPECT_EQ(back.recovered, joint_bit(hand));
  EXPECT_EQ(rig->segment.esc(position).al_state(), reg::AlState::op);
}

}  // namespace
}  // namespace rescue::ecat
