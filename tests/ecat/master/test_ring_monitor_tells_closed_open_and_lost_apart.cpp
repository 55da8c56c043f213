// The ring monitor (ecat/master/ring_monitor.hpp) over a redundant link and a two-port fake segment
// of 6 slaves: the ring closed, open at each cable (the place named by the slaves either side, or the
// master's port), and broken twice (the slaves between the cuts reachable from neither port) are
// told apart from the first frame after the change (broken twice: confirmed by the second); each
// change is reported exactly once, the repair too, with its place; the returns of a frame during
// which a cable changed are no evidence. Virtual time.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "ecat/codec/registers.hpp"
#include "ecat/master/ring_monitor.hpp"
#include "tests/support/two_port_rig.hpp"

namespace rescue::ecat {
namespace {

using test::kRingRigSlaves;

class RingWatch : public ::testing::Test {
 protected:
  RingWatch() {
    std::array<std::uint8_t, kMaxSlaves> planned{};
    planned.fill(RingMonitor::kNoSlavePosition);
    for (std::size_t i = 0; i < kRingRigSlaves; ++i) planned[i] = static_cast<std::uint8_t>(i);
    monitor.start(planned, kRingRigSlaves);
  }

  // One cycle: a frame with the DL-status BRD, its copies observed.
  void cycle() {
    ++n;
    FrameBuilder& frame = rig.link.begin();
    ASSERT_TRUE(frame.add(Command::BRD, rig.link.index(), make_address(0, reg::kDlStatus), 2).ok());
    (void)rig.link.exchange(rig.segment.clock().now() + 100 * hal::kNsPerUs);
    const CopyReturns& r = rig.link.copy_returns();
    monitor.observe(n, rig.segment.clock().now(), r, r.counters.main[0], r.counters.ring[0]);
    RingReport report;
    while (monitor.pop_report(report)) reports.push_back(report);
  }
  void cycles(int count) {
    for (int i = 0; i < count; ++i) cycle();
  }

  test::TwoPortRig rig;
  RingMonitor monitor;
  std::uint64_t n = 0;
  std::vector<RingReport> reports;
};

TEST_F(RingWatch, ClosedRingStaysClosedWithoutReports) {
  cycles(20);
  EXPECT_EQ(monitor.status().state, RingState::closed);
  EXPECT_TRUE(reports.empty());
}

TEST_F(RingWatch, EachSingleBreakIsReportedOnceWithItsPlaceAndSoIsItsRepair) {
  for (std::size_t cable = 0; cable <= kRingRigSlaves; ++cable) {
    SCOPED_TRACE("cable " + std::to_string(cable));
    reports.clear();
    rig.segment.cut(cable);
    const std::uint64_t cut_in = n + 1;
    cycles(10);
    ASSERT_EQ(reports.size(), 1U);
    EXPECT_EQ(reports[0].kind, RingEventKind::opened);
    EXPECT_EQ(reports[0].cycle, cut_in) << "decided from the first frame after the cut";
    const std::uint8_t before = cable == 0 ? kMainPort : static_cast<std::uint8_t>(cable - 1);
    const std::uint8_t after = cable == kRingRigSlaves ? kRingPort : static_cast<std::uint8_t>(cable);
    EXPECT_EQ(reports[0].before, before);
    EXPECT_EQ(reports[0].after, after);
    EXPECT_EQ(monitor.status().state, RingState::open);
    EXPECT_EQ(monitor.status().unreachable, 0U);

    rig.segment.restore(cable);
    const std::uint64_t repaired_in = n + 1;
    cycles(10);
    ASSERT_EQ(reports.size(), 2U);
    EXPECT_EQ(reports[1].kind, RingEventKind::closed);
    EXPECT_EQ(reports[1].cycle, repaired_in);
    EXPECT_EQ(reports[1].before, before) << "the repair names the place repaired";
    EXPECT_EQ(reports[1].after, after);
    EXPECT_EQ(monitor.status().state, RingState::closed);
  }
  EXPECT_EQ(monitor.status().breaks, kRingRigSlaves + 1);
  EXPECT_EQ(monitor.status().repairs, kRingRigSlaves + 1);
}

TEST_F(RingWatch, TwoBreaksMakeExactlyTheSlavesBetweenThemUnreachable) {
  rig.segment.cut(2);
  cycles(3);
  rig.segment.cut(5);  // slaves 2, 3, 4 are now between the cuts
  cycles(3);
  ASSERT_EQ(reports.size(), 2U);
  EXPECT_EQ(reports[1].kind, RingEventKind::split);
  EXPECT_EQ(reports[1].cycle, 4U) << "confirmed by the second frame, dated from the first";
  EXPECT_EQ(reports[1].unreachable, slave_bit(2) | slave_bit(3) | slave_bit(4));
  EXPECT_EQ(reports[1].before, 1U);
  EXPECT_EQ(reports[1].after, 5U);
  EXPECT_EQ(monitor.status().state, RingState::lost);
  rig.segment.restore(5);
  cycles(3);
  ASSERT_EQ(reports.size(), 3U);
  EXPECT_EQ(reports[2].kind, RingEventKind::opened);
  EXPECT_EQ(reports[2].before, 1U);
  EXPECT_EQ(reports[2].after, 2U);
  rig.segment.restore(2);
  cycles(3);
  ASSERT_EQ(reports.size(), 4U);
  EXPECT_EQ(reports[3].kind, RingEventKind::closed);
  EXPECT_EQ(monitor.status().breaks, 1U) << "one break: closed to open (the second cut split an open ring)";
}

TEST_F(RingWatch, NoCopyBackIsNoEvidence) {
  rig.segment.cut(0);
  rig.segment.cut(kRingRigSlaves);
  cycles(5);
  EXPECT_EQ(monitor.status().state, RingState::closed);
  EXPECT_TRUE(reports.empty());
}

// The returns of one frame, fed to the monitor as the link hands them over.
CopyReturns returns(bool main_back, Port main_on, bool ring_back, Port ring_on) {
  CopyReturns r;
  r.main_back = main_back;
  r.main_on = main_on;
  r.ring_back = ring_back;
  r.ring_on = ring_on;
  return r;
}

TEST_F(RingWatch, ARepairWhileTheFrameIsInFlightIsNeitherASecondBreakNorTheRepairYet) {
  rig.segment.cut(3);
  cycles(3);
  ASSERT_EQ(reports.size(), 1U);
  // The main copy turned at the break (slaves 0..2), the ring copy, sent after the repair, went
  // round the closed ring unprocessed (0 slaves) and came back on the main NIC too: as over veth.
  monitor.observe(++n, 0, returns(true, Port::main, true, Port::main), 3, 0);
  RingReport report;
  EXPECT_FALSE(monitor.pop_report(report)) << to_string(report.kind);
  EXPECT_EQ(monitor.status().state, RingState::open);
  EXPECT_EQ(monitor.status().transients, 1U);
  rig.segment.restore(3);
  cycle();
  ASSERT_EQ(reports.size(), 2U);
  EXPECT_EQ(reports[1].kind, RingEventKind::closed);
  EXPECT_EQ(reports[1].before, 2U);
  EXPECT_EQ(reports[1].after, 3U);
}

TEST_F(RingWatch, ACutWhileTheFrameIsInFlightIsReportedOnceByTheNextFrame) {
  cycles(2);
  // The main copy went round the still closed ring (6 slaves), the ring copy, sent after the cut,
  // turned at it (slaves 3..5): 9 counted in all.
  monitor.observe(++n, 0, returns(true, Port::ring, true, Port::ring), 6, 3);
  EXPECT_EQ(monitor.status().state, RingState::closed);
  EXPECT_EQ(monitor.status().transients, 1U);
  rig.segment.cut(3);
  cycles(2);
  ASSERT_EQ(reports.size(), 1U);
  EXPECT_EQ(reports[0].kind, RingEventKind::opened);
  EXPECT_EQ(reports[0].before, 2U);
  EXPECT_EQ(reports[0].after, 3U);
}

TEST_F(RingWatch, SlavesReachableFromNeitherPortInOneFrameOnlyAreNotReportedLost) {
  rig.segment.cut(3);
  cycles(2);
  ASSERT_EQ(reports.size(), 1U);
  // The ring copy lost in flight: the main copy's 3 slaves alone, as if 3..5 were cut off.
  monitor.observe(++n, 0, returns(true, Port::main, false, Port::ring), 3, 0);
  cycles(2);
  EXPECT_EQ(reports.size(), 1U) << "no split, no second opened";
  EXPECT_EQ(monitor.status().state, RingState::open);
  EXPECT_EQ(monitor.status().transients, 1U);
}

TEST_F(RingWatch, TheReportReadsAsOneLineNamingBothSides) {
  rig.segment.cut(3);
  cycle();
  ASSERT_EQ(reports.size(), 1U);
  std::array<char, 160> line{};
  (void)describe(reports[0], rig.plan, line.data(), line.size());
  EXPECT_STREQ(line.data(), "ring open between s2 (position 2) and s3 (position 3) (cycle 1)");
}

}  // namespace
}  // namespace rescue::ecat
