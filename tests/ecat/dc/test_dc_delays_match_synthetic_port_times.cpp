// Propagation delays computed from port receive times equal the true arrival times of a frame in a
// synthetic model of the robot's tree (per-slave forwarding delay, per-cable wire delay, clocks
// with arbitrary offsets that wrap at 32 bits).
#include <gtest/gtest.h>

#include <cstdint>

#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/dc/dc_delay.hpp"

namespace rescue::ecat {
namespace {

using drivers::kRobotNetworkPlan;

struct Model {
  SlaveMask present{kAllSlaves};
  std::array<std::int64_t, kMaxSlaves> forward_ns{};   // receive -> transmit inside the ESC
  std::int64_t return_extra_ns{0};                      // return path slower than the forward path
  std::array<std::int64_t, kMaxSlaves> wire_ns{};      // cable into the slave, each way
  std::array<std::uint64_t, kMaxSlaves> clock_offset{};
  std::array<std::int64_t, kMaxSlaves> arrival{};      // true time the frame reached port 0
  std::array<PortReceiveTimes, kMaxSlaves> latch{};

  std::uint32_t local(std::size_t s, std::int64_t t) const {
    return static_cast<std::uint32_t>(static_cast<std::uint64_t>(t) + clock_offset[s]);
  }
  // Returns the time the frame leaves `s` through port 0 on its way back; `hop` is the parent's
  // forwarding delay, the same on the way back (the formula's assumption) plus return_extra_ns.
  std::int64_t visit(std::size_t s, std::int64_t t_in, std::int64_t hop) {
    arrival[s] = t_in;
    latch[s].port[0] = local(s, t_in);
    std::int64_t t = t_in;
    const ChildPorts ports = child_ports(kRobotNetworkPlan, present, s);
    for (std::size_t k = 0; k < ports.count; ++k) {
      const std::size_t c = ports.child[k];
      const std::int64_t back = visit(c, t + forward_ns[s] + wire_ns[c], forward_ns[s]);
      t = back + wire_ns[c];
      latch[s].port[ports.port[k]] = local(s, t);
    }
    return t + hop + return_extra_ns;
  }
};

Model make_model(SlaveMask present, std::int64_t return_extra_ns = 0) {
  Model m;
  m.present = present;
  m.return_extra_ns = return_extra_ns;
  for (std::size_t s = 0; s < kMaxSlaves; ++s) {
    m.forward_ns[s] = 140 + static_cast<std::int64_t>((s * 37) % 60);
    m.wire_ns[s] = 5 + static_cast<std::int64_t>((s * 13) % 40);  // 1 to 8 m of cable
    m.clock_offset[s] = 0xFFFFF000ULL * (s + 1) + s * 977;        // 32-bit views wrap
  }
  (void)m.visit(0, 1'000'000, 0);
  return m;
}

TEST(DcDelays, EqualTrueArrivalTimesInTheFullTree) {
  const Model m = make_model(kAllSlaves);
  const Result<DcDelays> delays = compute_propagation_delays(kRobotNetworkPlan, kAllSlaves, m.latch);
  ASSERT_TRUE(delays.ok()) << delays.error().what;
  for (std::size_t s = 0; s < kMaxSlaves; ++s) {
    EXPECT_EQ(delays.value()[s], static_cast<std::uint32_t>(m.arrival[s] - m.arrival[0])) << kRobotNetworkPlan[s].name;
  }
  // Frame order is the order of arrival: delays grow along the frame.
  for (std::size_t s = 1; s < kMaxSlaves; ++s) EXPECT_GT(delays.value()[s], delays.value()[s - 1]);
}

TEST(DcDelays, EqualTrueArrivalTimesWithBranchesCut) {
  // Right arm cut at the elbow, torso cut at the neck: the slaves behind are absent.
  SlaveMask present = kAllSlaves;
  for (std::size_t s : {5u, 6u, 7u, 8u, 14u, 15u}) present &= ~slave_bit(s);
  const Model m = make_model(present);
  const Result<DcDelays> delays = compute_propagation_delays(kRobotNetworkPlan, present, m.latch);
  ASSERT_TRUE(delays.ok()) << delays.error().what;
  for (std::size_t s = 0; s < kMaxSlaves; ++s) {
    if ((present & slave_bit(s)) == 0) continue;
    EXPECT_EQ(delays.value()[s], static_cast<std::uint32_t>(m.arrival[s] - m.arrival[0])) << kRobotNetworkPlan[s].name;
  }
}

TEST(DcDelays, AsymmetricPathsErrByHalfTheAsymmetryPerHop) {
  // A return path 20 ns slower per hop than assumed: each hop's estimate is 10 ns long.
  const Model m = make_model(kAllSlaves, 20);
  const DcDelays delays = compute_propagation_delays(kRobotNetworkPlan, kAllSlaves, m.latch).value();
  EXPECT_EQ(delays[1], static_cast<std::uint32_t>(m.arrival[1] - m.arrival[0]) + 10);  // one hop
  EXPECT_EQ(delays[2], static_cast<std::uint32_t>(m.arrival[2] - m.arrival[0]) + 20);  // two hops
}

TEST(DcDelays, ChildPortsFollowProcessingOrder0312) {
  const ChildPorts a = child_ports(kRobotNetworkPlan, kAllSlaves, 0);
  ASSERT_EQ(a.count, 3);
  EXPECT_EQ(a.port[0], 3);  // junction_b first
  EXPECT_EQ(a.child[0], 1);
  EXPECT_EQ(a.port[1], 1);  // torso
  EXPECT_EQ(a.child[1], 13);
  EXPECT_EQ(a.port[2], 2);  // left arm
  EXPECT_EQ(a.child[2], 16);
  EXPECT_EQ(child_ports(kRobotNetworkPlan, kAllSlaves, 22).count, 0);  // l_hand ends its branch
}

TEST(DcDelays, RefuseASlaveWhoseUpstreamIsAbsent) {
  const Model m = make_model(kAllSlaves);
  const SlaveMask present = kAllSlaves & ~slave_bit(1);  // junction_b missing, its branches not
  const Result<DcDelays> delays = compute_propagation_delays(kRobotNetworkPlan, present, m.latch);
  ASSERT_FALSE(delays.ok());
  EXPECT_EQ(delays.error().code, Errc::mismatch);
  EXPECT_EQ(delays.error().detail0, 2u);  // r_shoulder_pitch hangs off junction_b
}

TEST(DcDelays, RefuseLatchTimesThatContradictTheTopology) {
  Model m = make_model(kAllSlaves);
  m.latch[0].port[3] = m.latch[0].port[0] + 10;  // junction_b's subtree "returned" in 10 ns
  const Result<DcDelays> delays = compute_propagation_delays(kRobotNetworkPlan, kAllSlaves, m.latch);
  ASSERT_FALSE(delays.ok());
  EXPECT_EQ(delays.error().code, Errc::malformed);
}

TEST(DcDelays, OffsetMakesEverySlaveAgreeOnTheWaveFront) {
  const Model m = make_model(kAllSlaves);
  const DcDelays delays = compute_propagation_delays(kRobotNetworkPlan, kAllSlaves, m.latch).value();
  const std::uint64_t epoch = 0x0123456789ABCDEFULL;
  for (std::size_t s = 0; s < kMaxSlaves; ++s) {
    // 64-bit local receive time as 0x0918 holds it.
    const std::uint64_t local64 = static_cast<std::uint64_t>(m.arrival[s]) + m.clock_offset[s];
    const std::uint64_t offset = system_time_offset(epoch, delays[s], local64);
    // At the same true instant (the reference's arrival), every system time reads `epoch`.
    const std::uint64_t local_at_ref = static_cast<std::uint64_t>(m.arrival[0]) + m.clock_offset[s];
    EXPECT_EQ(local_at_ref + offset, epoch) << s;
  }
}

}  // namespace
}  // namespace rescue::ecat
