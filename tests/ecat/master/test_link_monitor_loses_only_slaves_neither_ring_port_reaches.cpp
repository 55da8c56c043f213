// The link monitor (the one loss decider) with cable redundancy counts the merged working counters:
// over a redundant link and a two-port fake segment of 6 slaves in one branch, a single cut at any
// cable loses no slave and every slave's inputs stay valid in every cycle; two cuts lose exactly
// the slaves between them (reachable from neither port), whatever their place in the branch, and
// no slave is ever marked valid while unreachable. Virtual time.
#include <gtest/gtest.h>

#include <string>

#include "ecat/codec/registers.hpp"
#include "ecat/master/link_monitor.hpp"
#include "tests/support/two_port_rig.hpp"

namespace rescue::ecat {
namespace {

using test::kRingRigSlaves;
constexpr SlaveMask kRigSlaves = (SlaveMask{1} << kRingRigSlaves) - 1;

class RedundantLosses : public ::testing::Test {
 protected:
  RedundantLosses() {
    monitor.set_redundant(true);
    monitor.start(kRigSlaves);
  }

  // One cycle as the master runs it: the branch's LRW and the probes the monitor asks for.
  void cycle() {
    ++n;
    std::array<ProbeRequest, kMaxSlaves> probes{};
    const std::size_t count = monitor.plan_probes(probes.data(), probes.size());
    FrameBuilder& frame = rig.link.begin();
    const BranchLayout& branch = rig.layout.branches[0];
    std::array<std::uint8_t, 2 * kRingRigSlaves> image{};
    ASSERT_TRUE(frame.add(Command::LRW, rig.link.index(), branch.logical_start, branch.length, ConstByteSpan(image.data(), branch.length)).ok());
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint16_t station = rig.plan[probes[i].position].station_address;
      ASSERT_TRUE(frame.add(Command::FPRD, rig.link.index(), make_address(station, reg::kAlStatus), 6).ok());
    }
    const Result<FrameView> back = rig.link.exchange(rig.segment.clock().now() + 100 * hal::kNsPerUs);
    std::array<std::uint16_t, kMaxBranches> wkc{};
    std::array<ProbeResult, kMaxSlaves> results{};
    if (back.ok()) {
      auto d = back.value().begin();
      wkc[0] = (*d).wkc();
      ++d;
      for (std::size_t i = 0; i < count; ++i, ++d) {
        results[i] = ProbeResult{probes[i].position, false, probes[i].watch, (*d).wkc(), load_le16((*d).data().data()),
                                 load_le16((*d).data().data() + 4), 0, false};
      }
    }
    monitor.observe(n, rig.segment.clock().now(), back.ok(), wkc, Span<const ProbeResult>(results.data(), count));
    LinkReport report;
    while (monitor.pop_report(report)) {
    }
  }

  test::TwoPortRig rig;
  LinkMonitor monitor{rig.plan, rig.layout};
  std::uint64_t n = 0;
};

TEST_F(RedundantLosses, ASingleCutAnywhereLosesNothing) {
  for (std::size_t cable = 0; cable <= kRingRigSlaves; ++cable) {
    SCOPED_TRACE("cable " + std::to_string(cable));
    rig.segment.restore_all();
    rig.segment.cut(cable);
    for (int i = 0; i < 20; ++i) {
      cycle();
      EXPECT_EQ(monitor.valid(), kRigSlaves);
    }
    EXPECT_EQ(monitor.lost(), 0U);
    EXPECT_EQ(monitor.in_exchange(), kRigSlaves);
  }
}

TEST_F(RedundantLosses, TwoCutsLoseExactlyTheSlavesBetweenThem) {
  rig.segment.cut(1);
  rig.segment.cut(3);  // slaves 1 and 2 between: mid-branch, the prefix rule would have blamed 4 and 5
  for (int i = 0; i < 20; ++i) {
    cycle();
    EXPECT_EQ(monitor.valid() & (slave_bit(1) | slave_bit(2)), 0U) << "cycle " << n;
  }
  EXPECT_EQ(monitor.lost(), slave_bit(1) | slave_bit(2));
  EXPECT_EQ(monitor.in_exchange(), kRigSlaves & ~(slave_bit(1) | slave_bit(2)));
  EXPECT_EQ(monitor.valid(), monitor.in_exchange());
}

}  // namespace
}  // namespace rescue::ecat
