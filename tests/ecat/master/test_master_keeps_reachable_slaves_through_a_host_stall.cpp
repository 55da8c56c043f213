// A host stall is a gap in the master's cycles (virtual time: the clock jumps between two cycles).
// One longer than the drives' SyncManager watchdog (100 ms, the ESC default the master keeps) takes
// every drive to SAFE-OP with AL status code 0x001B: the simulated ESCs do what real ones do. That
// is the master's own silence, not a link fault: no reachable slave is reported lost or not
// operational for it, every joint stays valid, and the master brings the drives back to OP
// (`watchdog_expired`, then `rearmed`), the drives can be enabled again. A link cut into l_elbow
// around such a stall (the flaky `run --scenario link-cut` under load: l_shoulder_* were reported
// "link not operational" and lost) still loses exactly l_elbow and the joints behind it.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "drivers/cia402/cia402_enable.hpp"
#include "ecat/codec/registers.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

constexpr hal::Nanoseconds kStall = 150 * hal::kNsPerMs;  // above the 100 ms watchdog

struct Observed {
  std::vector<LinkReport> reports;
  JointMask ever_invalid_healthy{0};
  JointMask reported(LinkEventKind kind) const {
    JointMask joints = 0;
    for (const LinkReport& r : reports) {
      if (r.kind == kind) joints |= drivers::joints_of_slaves(r.slaves);
    }
    return joints;
  }
};

class HostStall : public ::testing::Test {
 protected:
  void SetUp() override {
    MasterOptions options = testing::fast_options();
    options.online_recovery = true;  // as `rescue-motion run`
    rig = testing::simulated_robot_in_op(options);
    ASSERT_EQ(rig->bus.master().state(), MasterState::op);
    // Every drive enabled, holding where it is.
    for (int i = 0; i < 200; ++i) {
      for (std::size_t j = 0; j < kJointCount; ++j) enable_step(j);
      (void)cycle();
    }
    for (std::size_t j = 0; j < kJointCount; ++j) ASSERT_TRUE(drivers::is_enabled(fb.joints[j].statusword)) << kJoints[j].name;
    LinkReport r;
    while (rig->bus.master().pop_report(r)) {}
  }
  void enable_step(std::size_t j) {
    refs[j].mode_of_operation = static_cast<std::int8_t>(ControlMode::cyclic_position);
    refs[j].target_position = fb.joints[j].position_actual;
    refs[j].controlword = drivers::controlword_towards_enabled(fb.joints[j].statusword, refs[j].controlword);
  }
  drivers::JointCycleResult cycle() { return rig->cycle(refs, fb); }

  // `periods` cycles; the host stalls for `stall` before the cycle `stall_before` (0: the first).
  Observed run(int periods, int stall_before, hal::Nanoseconds stall, JointMask healthy) {
    Observed o;
    for (int i = 0; i < periods; ++i) {
      if (i == stall_before) rig->clock.advance(stall);
      const drivers::JointCycleResult r = cycle();
      EXPECT_TRUE(r.frame_received);
      // From the cycle after the cut's first frame (the counter places the cut from then on).
      if (i > 0) o.ever_invalid_healthy |= healthy & ~r.valid;
      LinkReport report;
      while (rig->bus.master().pop_report(report)) o.reports.push_back(report);
    }
    return o;
  }
  bool drives_in_op(JointMask joints) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((joints & joint_bit(j)) != 0 && rig->segment.esc(slave_position_of_joint(j)).al_state() != reg::AlState::op) return false;
    }
    return true;
  }

  std::unique_ptr<SimulatedRobotRig> rig;
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
};

TEST_F(HostStall, LongerThanTheWatchdogReArmsEveryDriveAndLosesNothing) {
  const Observed o = run(60, 5, kStall, kAllJoints);
  EXPECT_EQ(o.reported(LinkEventKind::lost), 0u);
  EXPECT_EQ(o.reported(LinkEventKind::not_operational), 0u);
  EXPECT_EQ(o.reported(LinkEventKind::watchdog_expired), kAllJoints) << "the stall took every drive out of OP";
  EXPECT_EQ(o.reported(LinkEventKind::rearmed), kAllJoints);
  EXPECT_EQ(o.ever_invalid_healthy, 0u) << "a stall costs no joint a cycle of inputs";
  EXPECT_TRUE(drives_in_op(kAllJoints)) << "the master brought every drive back to OP";
  EXPECT_EQ(rig->bus.master().monitor().out_of_exchange(), 0u);
  EXPECT_GE(rig->bus.master().monitor().watchdog_check_rounds(), 1u);
  for (const LinkReport& r : o.reports) {
    if (r.kind == LinkEventKind::watchdog_expired) {
      EXPECT_EQ(r.al_status_code, reg::al_code::kSyncManagerWatchdog);
      EXPECT_GE(r.found[0], 150u) << "the silence in ms";
    }
  }
  // The drives, disabled by their SAFE-OP, can be enabled again.
  for (int i = 0; i < 100; ++i) {
    for (std::size_t j = 0; j < kJointCount; ++j) enable_step(j);
    (void)cycle();
  }
  for (std::size_t j = 0; j < kJointCount; ++j) EXPECT_TRUE(drivers::is_enabled(fb.joints[j].statusword)) << kJoints[j].name;
}

TEST_F(HostStall, ShorterThanTheWatchdogChangesNothing) {
  const Observed o = run(30, 5, 99 * hal::kNsPerMs, kAllJoints);
  EXPECT_TRUE(o.reports.empty());
  EXPECT_TRUE(drives_in_op(kAllJoints));
}

// The stall before the cut's first frame, after it, or after its second: the probes that follow the
// short counter meet the upstream drives in SAFE-OP by their watchdog.
class HostStallAtACut : public HostStall, public ::testing::WithParamInterface<int> {};

TEST_P(HostStallAtACut, LosesExactlyTheJointsBehindTheCut) {
  const std::size_t elbow = joint_index_by_name("l_elbow");
  const JointMask behind = joints_lost_by_link_failure_at(elbow);
  const JointMask healthy = kAllJoints & ~behind;
  ASSERT_TRUE(rig->segment.cut_link(slave_position_of_joint(elbow)).ok());
  const Observed o = run(60, GetParam(), kStall, healthy);
  EXPECT_EQ(o.reported(LinkEventKind::lost), behind);
  EXPECT_EQ(o.reported(LinkEventKind::not_operational), 0u) << "l_shoulder_* are reachable: the stall is no link fault";
  EXPECT_EQ(o.reported(LinkEventKind::recovered), 0u);
  EXPECT_EQ(o.reported(LinkEventKind::watchdog_expired), healthy);
  EXPECT_EQ(o.reported(LinkEventKind::rearmed), healthy);
  EXPECT_EQ(o.ever_invalid_healthy, 0u);
  EXPECT_EQ(drivers::joints_of_slaves(rig->bus.master().monitor().out_of_exchange()), behind);
  EXPECT_TRUE(drives_in_op(healthy));
}

INSTANTIATE_TEST_SUITE_P(StallBeforeFrame, HostStallAtACut, ::testing::Values(0, 1, 2, 3),
                         [](const ::testing::TestParamInfo<int>& p) { return "frame_" + std::to_string(p.param); });

}  // namespace
}  // namespace rescue::ecat
