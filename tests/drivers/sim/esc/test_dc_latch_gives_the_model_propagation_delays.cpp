// A broadcast write of 0x0900 latches, on every ESC, the local time at which that frame reached each
// of its ports. The delays a master derives from those times (through the junction tree, as
// ETG.1020 describes) are the model's propagation delays: exactly when every ESC forwards
// symmetrically, and within the model's known asymmetry when processing and forwarding delays differ,
// on the tree and on the ring's line (where that asymmetry adds up over 22 hops).
#include <cstdio>
#include <cstdlib>

#include "core/robot/robot_ring.hpp"
#include "tests/support/dc_master_steps.hpp"

namespace rescue::drivers::testing {
namespace {

// What the master's symmetric assumption misses on the hop into `p`: the parent sends the frame
// out (processing delay if this is its first open port after port 0, else forwarding delay), the
// child sends it back (forwarding delay if it has a branch behind it, else processing delay).
std::int64_t hop_asymmetry(const SimulatedSegment& segment, std::size_t p) {
  const SegmentSlave& s = segment.slave(p);
  const SegmentSlave& parent = segment.slave(s.upstream);
  bool first_after_port0 = true;
  for (const unsigned port : {3U, 1U, 2U}) {
    if (port == s.upstream_port) break;
    if (segment.child(s.upstream, port) != kUpstreamIsMaster) first_after_port0 = false;
  }
  const hal::Nanoseconds out = first_after_port0 ? parent.esc.processing_delay_ns : parent.esc.forwarding_delay_ns;
  bool has_branch = false;
  for (unsigned port = 1; port < kMaxEscPorts; ++port) has_branch = has_branch || segment.child(p, port) != kUpstreamIsMaster;
  const hal::Nanoseconds back = has_branch ? s.esc.forwarding_delay_ns : s.esc.processing_delay_ns;
  return (back - out) / 2;
}

TEST(DcLatch, EveryPortLatchesTheTimeTheFrameReachedIt) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  const LatchedTimes t = latch_receive_times(*rig);
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    // Port 0 and the processing unit latch the same instant (as real ESCs show).
    EXPECT_EQ(static_cast<std::uint32_t>(t.epu[p]), t.port[p][0]) << p;
  }
  // Latch again and check against the model's arrival times of that very frame.
  const auto latch = rig->write(Command::BWR, 0, reg::kDcReceiveTimePort0, le32(0));
  ASSERT_EQ(latch.wkc, kSlaveCount);
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    const Esc& esc = rig->segment.esc(p);
    EXPECT_EQ(esc.register_u64(reg::kDcReceiveTimeEpu), esc.local_time_at(rig->segment.last_arrival(p))) << p;
  }
}

TEST(DcLatch, PortsWithoutTheFrameKeepTheirOldValue) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  const LatchedTimes first = latch_receive_times(*rig);
  rig->wait(hal::kNsPerMs);
  const LatchedTimes second = latch_receive_times(*rig);
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    for (unsigned port = 1; port < 4; ++port) {
      if (rig->segment.child(p, port) == kUpstreamIsMaster) {
        EXPECT_EQ(first.port[p][port], second.port[p][port]) << p << ":" << port;
      } else {
        EXPECT_NE(first.port[p][port], second.port[p][port]) << p << ":" << port;
      }
    }
  }
}

TEST(DcLatch, MasterDelaysEqualTheModelWhenForwardingIsSymmetric) {
  RobotSegmentOptions options;
  options.max_drift_ppm = 100.0;
  auto rig = Rig::robot(options);
  // Same processing and forwarding delay in every ESC: the symmetric assumption holds.
  std::array<SegmentSlave, kSlaveCount> slaves{};
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    slaves[p] = rig->segment.slave(p);
    slaves[p].esc.processing_delay_ns = 300;
    slaves[p].esc.forwarding_delay_ns = 300;
  }
  ASSERT_TRUE(rig->segment.build(Span<const SegmentSlave>(slaves), rig->now).ok());
  rig->assign_station_addresses();
  const LatchedTimes t = latch_receive_times(*rig);
  (void)rig->write(Command::BWR, 0, reg::kDcReceiveTimePort0, le32(0));  // model arrivals of a latch frame
  const auto delays = master_delays(*rig, t);
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    const hal::Nanoseconds model = rig->segment.last_arrival(p) - rig->segment.last_arrival(0);
    // Within 2 ns: latched times are whole nanoseconds of drifting (+-100 ppm) local clocks.
    EXPECT_NEAR(static_cast<double>(delays[p]), static_cast<double>(model), 2.0) << kSlaves[p].name;
  }
}

TEST(DcLatch, MasterDelaysDifferFromTheModelOnlyByTheForwardingAsymmetry) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  const LatchedTimes t = latch_receive_times(*rig);
  (void)rig->write(Command::BWR, 0, reg::kDcReceiveTimePort0, le32(0));
  const auto delays = master_delays(*rig, t);
  std::array<std::int64_t, kSlaveCount> expected_error{};
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    const std::size_t parent = rig->segment.slave(p).upstream;
    expected_error[p] = expected_error[parent] + hop_asymmetry(rig->segment, p);
    const hal::Nanoseconds model = rig->segment.last_arrival(p) - rig->segment.last_arrival(0);
    EXPECT_NEAR(static_cast<double>(delays[p] - model), static_cast<double>(expected_error[p]), 2.0 + static_cast<double>(p) * 0.5)
        << kSlaves[p].name;
    // The error a master makes stays in the tens of nanoseconds even at the end of an arm.
    EXPECT_LT(std::abs(delays[p] - model), 60) << kSlaves[p].name;
  }
}

// The ring's delay bias (docs/redundancy.md "DC on the ring"): on the ring's line, its end closed
// for the latch as Master::close_ring_end closes it, every hop but the last is a parent's processing
// unit out and a child's forwarding back, so the symmetric split errs by (forwarding - processing)
// / 2, about -5 ns, on each of them and the error adds up along the line: about -105 ns at l_hand,
// against -40 to -50 ns at the end of the tree's deepest branch (8 or 9 hops). The same arithmetic
// as the tree's, on 22 hops in a row.
TEST(DcLatch, OnTheRingLineTheMasterDelaysErrByTheForwardingAsymmetryOfEveryHop) {
  std::int64_t deepest_tree_error = 0;
  {
    auto tree = Rig::robot();
    tree->assign_station_addresses();
    const LatchedTimes t = latch_receive_times(*tree);
    (void)tree->write(Command::BWR, 0, reg::kDcReceiveTimePort0, le32(0));
    const auto delays = master_delays(*tree, t);
    for (std::size_t p = 1; p < kSlaveCount; ++p) {
      const hal::Nanoseconds model = tree->segment.last_arrival(p) - tree->segment.last_arrival(0);
      if (std::abs(delays[p] - model) > std::abs(deepest_tree_error)) deepest_tree_error = delays[p] - model;
    }
  }
  RobotSegmentOptions options;
  options.ring = true;
  auto rig = Rig::robot(options);
  rig->assign_station_addresses();
  const auto end = static_cast<std::uint16_t>(kStationAddressBase + kRingReturnSlave);
  const std::uint16_t control = rig->read16(end, reg::kDlControl);
  ASSERT_EQ(rig->write16(end, reg::kDlControl,
                         static_cast<std::uint16_t>(control | (0x03U << reg::dl_control_loop_shift(kRingReturnPort)))),
            1);
  const LatchedTimes t = latch_receive_times(*rig);
  (void)rig->write(Command::BWR, 0, reg::kDcReceiveTimePort0, le32(0));
  ASSERT_FALSE(rig->last_outcome.port == MasterPort::ring) << "the ring's end closed: the latch comes back on main";
  const auto delays = master_delays(*rig, t);
  std::array<std::int64_t, kSlaveCount> expected_error{};
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    const std::size_t parent = rig->segment.slave(p).upstream;
    expected_error[p] = expected_error[parent] + hop_asymmetry(rig->segment, p);
    const hal::Nanoseconds model = rig->segment.last_arrival(p) - rig->segment.last_arrival(0);
    EXPECT_NEAR(static_cast<double>(delays[p] - model), static_cast<double>(expected_error[p]), 2.0 + static_cast<double>(p) * 0.5)
        << kSlaves[p].name;
  }
  const std::size_t last = kSlaveCount - 1;
  const hal::Nanoseconds last_model = rig->segment.last_arrival(last) - rig->segment.last_arrival(0);
  std::printf("delay error at the end of the ring's line (l_hand, 22 hops): %lld ns (the hops' asymmetries: %lld ns); "
              "the tree's largest: %lld ns\n",
              static_cast<long long>(delays[last] - last_model), static_cast<long long>(expected_error[last]),
              static_cast<long long>(deepest_tree_error));
  EXPECT_LT(delays[last] - last_model, -80) << "the line's hops add up";
  EXPECT_GT(std::abs(delays[last] - last_model), 2 * std::abs(deepest_tree_error)) << "more than twice the tree's";
}

TEST(DcLatch, PropagationDelaysGrowAlongEachBranchAndDifferPerPosition) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  (void)rig->write(Command::BWR, 0, reg::kDcReceiveTimePort0, le32(0));
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    const std::size_t parent = rig->segment.slave(p).upstream;
    // Each hop: the parent's forwarding plus a cable with two PHYs, about half a microsecond.
    const hal::Nanoseconds hop = rig->segment.last_arrival(p) - rig->segment.last_arrival(parent);
    EXPECT_GT(hop, 400) << kSlaves[p].name;
    EXPECT_LT(hop, 2'000'000) << kSlaves[p].name;  // the first joint of a later branch waits for earlier ones
  }
  // Branches hang off the junctions in the order 3, 1, 2: the torso's first joint (junction_a port
  // 1) sees the frame only after the whole of junction_b's subtree.
  EXPECT_GT(rig->segment.last_arrival(13), rig->segment.last_arrival(12));
}

}  // namespace
}  // namespace rescue::drivers::testing
