// Lost-slave detection logic against a model of the robot's branches (reachability, AL state and
// FMMU activation per slave; LRW adds 3 per reached slave in OP with active FMMUs): a cut at any
// joint is reported as exactly that joint and everything behind it, one cycle after the working
// counter showed it, while every other slave stays valid in every cycle; restoration is reported
// and never re-used silently; a slave leaving OP and a dead network are reported too; a watchdog
// expiry after the master's silence is re-armed, not reported not operational.
#include <gtest/gtest.h>

#include <vector>

#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/master/link_monitor.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat {
namespace {

using drivers::kRobotImageLayout;
using drivers::kRobotNetworkPlan;

struct BranchModel {
  SlaveMask reachable{kAllSlaves};
  SlaveMask fmmu_active{kAllSlaves};
  std::array<std::uint16_t, kMaxSlaves> al_state{};
  bool frames_pass{true};

  BranchModel() { al_state.fill(static_cast<std::uint16_t>(reg::AlState::op)); }

  void cut_link_into(std::size_t position) { reachable &= ~subtree_of(kRobotNetworkPlan, position); }
  void restore_all() { reachable = kAllSlaves; }

  std::array<std::uint16_t, kMaxBranches> lrw_wkc() const {
    std::array<std::uint16_t, kMaxBranches> wkc{};
    for (std::size_t b = 0; b < kMaxBranches; ++b) {
      const BranchLayout& branch = kRobotImageLayout.branches[b];
      for (std::size_t i = 0; i < branch.slave_count; ++i) {
        const SlaveMask bit = slave_bit(branch.slaves[i]);
        if ((reachable & bit) == 0 || (fmmu_active & bit) == 0) continue;
        const bool op = al_state[branch.slaves[i]] == static_cast<std::uint16_t>(reg::AlState::op);
        wkc[b] = static_cast<std::uint16_t>(wkc[b] + (op ? 3 : 1));  // SAFE-OP: inputs only
      }
    }
    return wkc;
  }
};

struct Harness {
  LinkMonitor monitor{kRobotNetworkPlan, kRobotImageLayout};
  BranchModel net;
  std::uint64_t cycle = 0;
  std::vector<LinkReport> reports;

  Harness() { monitor.start(kAllSlaves); }

  // One master cycle against the model; returns the slaves valid in it.
  SlaveMask run_cycle() {
    ProbeRequest requests[kMaxSlaves];
    const std::size_t n = monitor.plan_probes(requests, kMaxSlaves);
    std::vector<ProbeResult> results;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t p = requests[i].position;
      const bool answers = (net.reachable & slave_bit(p)) != 0;
      ProbeResult r;
      r.position = requests[i].position;
      r.had_clear = requests[i].clear_fmmus;
      if (answers && r.had_clear) {
        net.fmmu_active &= ~slave_bit(p);
        r.clear_wkc = 1;
      }
      r.status_wkc = answers ? 1 : 0;
      r.al_status = answers ? net.al_state[p] : 0;
      r.al_status_code = answers && net.al_state[p] != 8 ? 0x001B : 0;
      results.push_back(r);
    }
    // Probes ride after the LRWs in the frame: the counters see the state before the clears.
    const SlaveMask fmmu_before = net.fmmu_active;
    for (const ProbeResult& r : results) {
      if (r.had_clear && r.clear_wkc != 0) net.fmmu_active |= slave_bit(r.position);
    }
    const auto wkc = net.lrw_wkc();
    net.fmmu_active = fmmu_before;
    ++cycle;
    monitor.observe(cycle, static_cast<hal::Nanoseconds>(cycle) * hal::kNsPerMs, net.frames_pass, wkc,
                    Span<const ProbeResult>(results.data(), results.size()));
    LinkReport r;
    while (monitor.pop_report(r)) reports.push_back(r);
    return monitor.valid();
  }
};

class LinkMonitorTest : public ::testing::Test, public Harness {};
class LinkMonitorCut : public ::testing::TestWithParam<std::size_t>, public Harness {};

TEST_F(LinkMonitorTest, HealthyNetworkIsAllValidAndQuiet) {
  for (int i = 0; i < 100; ++i) EXPECT_EQ(run_cycle(), kAllSlaves & ~slave_bit(0) & ~slave_bit(1));
  EXPECT_TRUE(reports.empty());
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    EXPECT_EQ(monitor.expected_wkc(b), 3 * kRobotImageLayout.branches[b].slave_count);
  }
}

TEST_P(LinkMonitorCut, ReportsExactlyTheLinkFailureSetAndKeepsTheRestValid) {
  const std::size_t j = GetParam();
  Harness& t = *this;
  {
    for (int i = 0; i < 5; ++i) (void)t.run_cycle();
    const JointMask expected = joints_lost_by_link_failure_at(j);
    const SlaveMask expected_slaves = drivers::slaves_of_joints(expected);
    const SlaveMask healthy = drivers::slaves_of_joints(kAllJoints & ~expected);

    t.net.cut_link_into(slave_position_of_joint(j));
    const std::uint64_t cut_cycle = t.cycle + 1;
    for (int i = 0; i < 10; ++i) {
      const SlaveMask valid = t.run_cycle();
      EXPECT_EQ(valid & healthy, healthy) << "a healthy joint missed cycle " << t.cycle;
      EXPECT_EQ(valid & expected_slaves, 0u) << "an unreachable joint was called valid in cycle " << t.cycle;
    }
    ASSERT_EQ(t.reports.size(), 1u);
    const LinkReport& r = t.reports[0];
    EXPECT_EQ(r.kind, LinkEventKind::lost);
    EXPECT_EQ(drivers::joints_of_slaves(r.slaves), expected);
    EXPECT_EQ(r.detected_cycle, cut_cycle);  // the working counter of the cut's own cycle
    EXPECT_EQ(r.cycle, cut_cycle + LinkMonitor::kLossConfirmFrames - 1);  // confirmed by the probes of the next frames
    EXPECT_EQ(r.branch, static_cast<std::uint8_t>(kJoints[j].branch));
    EXPECT_EQ(t.monitor.lost(), expected_slaves);
    for (std::size_t b = 0; b < kMaxBranches; ++b) {
      EXPECT_EQ(t.monitor.expected_wkc(b), t.net.lrw_wkc()[b]) << "expectation follows the loss";
    }
  }
}

TEST_F(LinkMonitorTest, RestoredLinkIsReportedOnceAndNotReused) {
  for (int i = 0; i < 3; ++i) (void)run_cycle();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  net.cut_link_into(elbow);
  for (int i = 0; i < 5; ++i) (void)run_cycle();
  const SlaveMask lost = monitor.lost();
  ASSERT_EQ(lost, subtree_of(kRobotNetworkPlan, elbow));

  net.restore_all();  // the slaves come back with their FMMUs still active (power kept)
  for (int i = 0; i < 40; ++i) {
    const SlaveMask valid = run_cycle();
    EXPECT_EQ(valid & lost, 0u) << "restored slaves are not used without re-integration";
  }
  ASSERT_GE(reports.size(), 2u) << "lost, then restored (possibly in parts)";
  SlaveMask restored = 0;
  for (std::size_t i = 1; i < reports.size(); ++i) {
    EXPECT_EQ(reports[i].kind, LinkEventKind::restored);
    restored |= reports[i].slaves;
  }
  EXPECT_EQ(restored, lost);
  EXPECT_EQ(monitor.restored(), lost);
  EXPECT_EQ(net.fmmu_active & lost, 0u) << "restored slaves are unmapped so they add nothing";
  for (std::size_t b = 0; b < kMaxBranches; ++b) EXPECT_EQ(monitor.expected_wkc(b), net.lrw_wkc()[b]);

  // Explicit re-integration (the owner configured them again).
  net.fmmu_active |= lost;
  monitor.reintegrated(lost, cycle, 0);
  EXPECT_EQ(run_cycle(), kAllSlaves & ~slave_bit(0) & ~slave_bit(1));
  EXPECT_EQ(reports.back().kind, LinkEventKind::reintegrated);
  EXPECT_EQ(reports.back().slaves, lost);
}

TEST_F(LinkMonitorTest, SlaveLeavingOpIsReportedWithItsAlStatusCode) {
  for (int i = 0; i < 3; ++i) (void)run_cycle();
  const std::size_t neck = slave_position_of_joint(joint_index_by_name("neck_pan"));
  net.al_state[neck] = static_cast<std::uint16_t>(reg::AlState::safe_op) | reg::kAlErrorBit;
  for (int i = 0; i < 5; ++i) (void)run_cycle();
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].kind, LinkEventKind::not_operational);
  EXPECT_EQ(reports[0].slaves, slave_bit(neck));
  EXPECT_EQ(reports[0].al_status_code, 0x001B);
  EXPECT_EQ(monitor.valid() & slave_bit(neck), 0u);
  // neck_tilt behind it keeps running.
  EXPECT_NE(monitor.valid() & slave_bit(neck + 1), 0u);
  EXPECT_EQ(net.fmmu_active & slave_bit(neck), 0u);
}

// The same AL status code after 60 ms without a returned frame: the drive's watchdog expired
// while nothing reached it, which is no link fault: reported `watchdog_expired`, left in the
// exchange for the master to re-arm (here a device whose counter in SAFE-OP falls short, so its
// branch stays suspect until it is back in OP), never `not_operational`.
TEST_F(LinkMonitorTest, AWatchdogExpiryAfterTheMastersSilenceIsReArmedNotReported) {
  for (int i = 0; i < 3; ++i) (void)run_cycle();
  const std::size_t neck = slave_position_of_joint(joint_index_by_name("neck_pan"));
  net.frames_pass = false;
  for (int i = 0; i < 60; ++i) (void)run_cycle();
  net.frames_pass = true;
  net.al_state[neck] = static_cast<std::uint16_t>(reg::AlState::safe_op) | reg::kAlErrorBit;
  for (int i = 0; i < 5; ++i) (void)run_cycle();
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].kind, LinkEventKind::watchdog_expired);
  EXPECT_EQ(reports[0].slaves, slave_bit(neck));
  EXPECT_EQ(reports[0].al_status_code, 0x001B);
  EXPECT_GE(reports[0].found[0], 60u);
  EXPECT_EQ(monitor.take_rearm_requests(), slave_bit(neck));
  EXPECT_EQ(monitor.take_rearm_requests(), 0u) << "taken once";
  EXPECT_EQ(monitor.out_of_exchange(), 0u);
  EXPECT_EQ(net.fmmu_active, kAllSlaves) << "its FMMUs stay on";
  // Acknowledged and back in OP (the master's part): one `rearmed`, every slave valid again.
  net.al_state[neck] = static_cast<std::uint16_t>(reg::AlState::op);
  monitor.rearmed(slave_bit(neck), cycle, static_cast<hal::Nanoseconds>(cycle) * hal::kNsPerMs);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(run_cycle(), kAllSlaves & ~slave_bit(0) & ~slave_bit(1));
  ASSERT_EQ(reports.size(), 2u);
  EXPECT_EQ(reports[1].kind, LinkEventKind::rearmed);
  EXPECT_EQ(reports[1].slaves, slave_bit(neck));
  EXPECT_EQ(monitor.watchdog_expiries(), 1u);
}

TEST_F(LinkMonitorTest, FramesThatDoNotComeBackAreMissingNeverLost) {
  for (int i = 0; i < 3; ++i) (void)run_cycle();
  net.frames_pass = false;
  for (int i = 0; i < 500; ++i) EXPECT_EQ(run_cycle(), 0u) << "nothing is valid without a frame";
  // Only the link-silence alarm (after LinkMonitor::kSilenceAlarm), never a loss.
  ASSERT_EQ(reports.size(), 1u) << "frames that did not come back are late or missing, not a lost network";
  EXPECT_EQ(reports[0].kind, LinkEventKind::silent);
  EXPECT_EQ(monitor.frames_missing(), 500u);
  EXPECT_EQ(monitor.frames_missing_in_row(), 500u);
  net.frames_pass = true;
  EXPECT_EQ(run_cycle(), kAllSlaves & ~slave_bit(0) & ~slave_bit(1));
  EXPECT_EQ(monitor.frames_missing_in_row(), 0u);
  EXPECT_EQ(monitor.in_exchange(), kAllSlaves);
}

TEST_F(LinkMonitorTest, ACutIsConfirmedByReturnedFramesOnlyWhateverGoesMissingBetween) {
  for (int i = 0; i < 3; ++i) (void)run_cycle();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  const SlaveMask lost = subtree_of(kRobotNetworkPlan, elbow);
  net.cut_link_into(elbow);
  const std::uint64_t cut_cycle = cycle + 1;
  // Returned, missing, missing, returned, missing, returned: the third returned frame confirms.
  const bool pattern[] = {true, false, false, true, false, true};
  for (std::size_t i = 0; i < sizeof pattern; ++i) {
    EXPECT_TRUE(reports.empty()) << "confirmed too early, before step " << i;
    net.frames_pass = pattern[i];
    (void)run_cycle();
  }
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].kind, LinkEventKind::lost);
  EXPECT_EQ(reports[0].slaves, lost);
  EXPECT_EQ(reports[0].detected_cycle, cut_cycle);
  EXPECT_EQ(reports[0].cycle, cut_cycle + 5);
  EXPECT_EQ(monitor.frames_missing(), 3u);
}

TEST_F(LinkMonitorTest, TwoShortFramesThenAFullOneAreNotALoss) {
  for (int i = 0; i < 3; ++i) (void)run_cycle();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  net.cut_link_into(elbow);
  (void)run_cycle();  // short counter
  (void)run_cycle();  // silent probe
  net.restore_all();
  for (int i = 0; i < 5; ++i) (void)run_cycle();
  EXPECT_TRUE(reports.empty()) << "kLossConfirmFrames returned frames in a row are needed";
  EXPECT_EQ(monitor.in_exchange(), kAllSlaves);
}

TEST_F(LinkMonitorTest, ATransientShortCounterIsAGlitchNotALoss) {
  (void)run_cycle();
  net.reachable &= ~slave_bit(22);
  (void)run_cycle();  // counter short this cycle...
  net.restore_all();
  (void)run_cycle();  // ...the probe finds it in OP
  (void)run_cycle();
  EXPECT_TRUE(reports.empty());
  EXPECT_EQ(monitor.glitches(), 1u);
  EXPECT_EQ(monitor.in_exchange(), kAllSlaves);
}

INSTANTIATE_TEST_SUITE_P(EveryJoint, LinkMonitorCut, ::testing::Range<std::size_t>(0, kJointCount),
                         [](const ::testing::TestParamInfo<std::size_t>& param) { return std::string(kJoints[param.param].name); });

}  // namespace
}  // namespace rescue::ecat
