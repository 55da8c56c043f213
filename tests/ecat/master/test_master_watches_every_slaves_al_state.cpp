// The AL state watch (issue 22; ecat/master/link_monitor.hpp item 6), on the simulated robot in
// virtual time: a drive whose application drops it from OP to SAFE-OP with an AL status code of its
// own (`safe-op SLAVE CODE` in the simulator) keeps adding to the working counter, so only reading its
// AL status shows it. Every slave in the exchange is read in turn in the cyclic frame: the drop is
// reported `not_operational` with its AL status and code within 10 periods, for each of the 21
// drives, and online recovery brings the drive back to OP. A power-cycled junction (no working
// counter counts it) is reported lost and recovered, the DC reference's clock set again. The watch costs at most
// ceil(23 / 8) = 3 reads per frame and no heap.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "drivers/sim/segment/fault_command.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

constexpr int kReportedWithin = 10;  // periods (the 10 ms at 1 ms)

MasterOptions recovery_options() {
  MasterOptions options = testing::fast_options();
  options.online_recovery = true;
  return options;
}

Status apply(testing::SimulatedRobotRig& rig, const char* text) {
  const Result<drivers::FaultCommand> command = drivers::parse_fault_command(text, std::strlen(text), rig.segment);
  if (!command.ok()) return command.error();
  return drivers::apply_fault_command(command.value(), rig.segment, rig.clock.now());
}

TEST(MasterAlStateWatch, ASafeOpDropOfEachDriveIsReportedWithinTenPeriodsAndRecovered) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  int worst = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::size_t position = slave_position_of_joint(j);
    char command[64];
    (void)std::snprintf(command, sizeof command, "safe-op %s 0x001A", kJoints[j].name);
    ASSERT_TRUE(apply(*rig, command).ok()) << command;
    ASSERT_EQ(rig->segment.esc(position).al_state(), reg::AlState::safe_op);
    int reported_after = -1;
    LinkReport found{};
    for (int i = 1; i <= 200 && reported_after < 0; ++i) {
      (void)rig->cycle(refs, fb);
      LinkReport r;
      while (rig->bus.master().pop_report(r)) {
        if (r.kind == LinkEventKind::not_operational && r.slaves == slave_bit(position)) {
          reported_after = i;
          found = r;
        }
        EXPECT_NE(r.kind, LinkEventKind::lost) << kJoints[j].name << ": a drop out of OP is not a loss";
      }
    }
    ASSERT_GT(reported_after, 0) << kJoints[j].name;
    EXPECT_LE(reported_after, kReportedWithin) << kJoints[j].name;
    EXPECT_EQ(found.al_status, static_cast<std::uint16_t>(reg::AlState::safe_op) | reg::kAlErrorBit) << kJoints[j].name;
    EXPECT_EQ(found.al_status_code, reg::al_code::kSynchronizationError) << kJoints[j].name;
    EXPECT_STREQ(reg::explain_al_status_code(found.al_status_code), "synchronization error");
    worst = std::max(worst, reported_after);
    // Recoverable: online recovery configures it again and brings it back to OP.
    bool recovered = false;
    for (int i = 0; i < 1000 && !recovered; ++i) {
      (void)rig->cycle(refs, fb);
      LinkReport r;
      while (rig->bus.master().pop_report(r)) recovered = recovered || (r.kind == LinkEventKind::recovered && r.slaves == slave_bit(position));
    }
    EXPECT_TRUE(recovered) << kJoints[j].name;
    EXPECT_EQ(rig->segment.esc(position).al_state(), reg::AlState::op) << kJoints[j].name;
  }
  EXPECT_GT(rig->bus.master().monitor().watch_reads(), 0u);
  std::printf("SAFE-OP drop (0x001A) of each of the 21 drives: reported within %d periods at worst\n", worst);
}

TEST(MasterAlStateWatch, AHealthyNetworkIsNeverReportedAndEverySlaveIsReadWithinEightPeriods) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  const std::uint64_t before = rig->bus.master().monitor().watch_reads();
  constexpr int kPeriods = 3000;
  for (int i = 0; i < kPeriods; ++i) {
    const drivers::JointCycleResult r = rig->cycle(refs, fb);
    EXPECT_EQ(r.valid, kAllJoints);
    LinkReport report;
    EXPECT_FALSE(rig->bus.master().pop_report(report)) << to_string(report.kind);
  }
  // 23 slaves in 8 periods: 3 reads per frame.
  const std::uint64_t reads = rig->bus.master().monitor().watch_reads() - before;
  EXPECT_GE(reads, static_cast<std::uint64_t>(kPeriods) * kSlaveCount / LinkMonitor::kAlWatchPeriods);
  EXPECT_LE(reads, static_cast<std::uint64_t>(kPeriods) * 3);
}

// Issue 35 item 9: a junction has no share in any working counter, so a silent AL status read was
// the only sign of its power cycle, and it was taken as no evidence: nothing was reported and the
// junction stayed "in OP" for the master while it was back in INIT without its station address.
// Now it is reported lost (watch read, then kLossConfirmFrames - 1 silent probes) and online
// recovery brings it back (a junction copies AL control into AL status, acknowledge bit included:
// recovery asks for INIT alone after acknowledging). The DC reference (junction_a) restarts its
// clock with it: recovery sets it again from the nearest DC slave's time, and every DC slave then
// agrees within `agreement_ns` of the first drive 500 periods later (docs/master.md: the first
// FRMW after the restart, before the loss is known, still disturbs the other clocks' drift loops).
void expect_power_cycled_slave_reported_lost_then_recovered(const char* name, std::int64_t agreement_ns) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  std::size_t position = kSlaveCount;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (std::strcmp(kSlaves[p].name, name) == 0) position = p;
  }
  ASSERT_LT(position, kSlaveCount) << name;
  char command[64];
  (void)std::snprintf(command, sizeof command, "power-cycle %s", name);
  ASSERT_TRUE(apply(*rig, command).ok()) << command;
  ASSERT_EQ(rig->segment.esc(position).al_state(), reg::AlState::init);
  int lost_after = -1;
  int recovered_after = -1;
  for (int i = 1; i <= 5000 && recovered_after < 0; ++i) {
    (void)rig->cycle(refs, fb);
    LinkReport r;
    while (rig->bus.master().pop_report(r)) {
      if ((r.kind == LinkEventKind::lost || r.kind == LinkEventKind::not_operational) && (r.slaves & slave_bit(position)) != 0 &&
          lost_after < 0) {
        lost_after = i;
      }
      if (r.kind == LinkEventKind::recovered && (r.slaves & slave_bit(position)) != 0) recovered_after = i;
    }
  }
  ASSERT_GT(lost_after, 0) << name << ": the power cycle is reported";
  EXPECT_LE(lost_after, static_cast<int>(LinkMonitor::kAlWatchPeriods + LinkMonitor::kLossConfirmFrames - 1)) << name;
  ASSERT_GT(recovered_after, 0) << name << ": recovered";
  EXPECT_EQ(rig->segment.esc(position).al_state(), reg::AlState::op) << name;
  EXPECT_EQ(rig->segment.esc(position).register_u16(reg::kStationAddress), rig->bus.master().plan()[position].station_address);
  for (int i = 0; i < 500; ++i) {
    const drivers::JointCycleResult c = rig->cycle(refs, fb);
    EXPECT_EQ(c.valid, kAllJoints) << name << " period " << i;
    if (c.valid != kAllJoints) break;
  }
  // The network keeps one time: every DC slave's system time (the reference's too, set again after
  // its restart; it was 15.5 ms off before) close to the first drive's, which never restarted.
  const hal::Nanoseconds now = rig->clock.now();
  const std::size_t drive = slave_position_of_joint(0);
  const auto drive_time = static_cast<std::int64_t>(rig->segment.esc(drive).system_time_at(now));
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    const auto t = static_cast<std::int64_t>(rig->segment.esc(p).system_time_at(now));
    EXPECT_LT(std::llabs(t - drive_time), agreement_ns) << name << ": " << kSlaves[p].name << " " << t << " vs " << drive_time;
  }
  std::printf("power-cycled %s: reported after %d periods, back in OP after %d\n", name, lost_after, recovered_after);
}

TEST(MasterAlStateWatch, APowerCycledJunctionIsReportedAndRecovered) {
  expect_power_cycled_slave_reported_lost_then_recovered("junction_b", 1000);
}

TEST(MasterAlStateWatch, APowerCycledDcReferenceIsReportedAndRecoveredWithItsClock) {
  expect_power_cycled_slave_reported_lost_then_recovered("junction_a", 2500);  // measured 1762 ns
}

TEST(MasterAlStateWatch, TheSimulatorRefusesADropItCannotMake) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  EXPECT_FALSE(apply(*rig, "safe-op junction_a 0x001A").ok()) << "junctions emulate their device";
  EXPECT_FALSE(apply(*rig, "safe-op l_elbow 0x10000").ok());
  EXPECT_FALSE(apply(*rig, "safe-op l_elbow").ok());
  ASSERT_TRUE(apply(*rig, "power-off r_hand").ok());
  EXPECT_FALSE(apply(*rig, "safe-op r_hand 0x001A").ok()) << "not powered";
}

}  // namespace
}  // namespace rescue::ecat
