// The robot's ring configuration (core/robot/robot_ring.hpp): with the ring closed a frame from the
// main port is processed by all 23 slaves once and comes back on the ring port. Every single cable
// cut (the 23 cables into the slaves' port 0 and the ring-return cable): the same broadcast read
// sent on main and on ring reaches every slave exactly once between them (working counters add up
// to 23), each coming back on its own port. Two cuts lose exactly the slaves between them;
// restoring the cables brings the ring back whole.
#include "core/robot/robot_ring.hpp"
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

// The cables of the ring: 0..22 the cable into that slave's port 0, 23 the ring-return cable.
constexpr std::size_t kRingReturnCable = kSlaveCount;
constexpr std::size_t kCableCount = kSlaveCount + 1;

std::unique_ptr<Rig> ring_robot() {
  RobotSegmentOptions options;
  options.ring = true;
  auto rig = Rig::robot(options);
  rig->assign_station_addresses();
  return rig;
}

void cut(Rig& rig, std::size_t cable) {
  ASSERT_TRUE((cable == kRingReturnCable ? rig.segment.cut_ring_cable() : rig.segment.cut_link(cable)).ok());
}
void restore(Rig& rig, std::size_t cable) {
  ASSERT_TRUE((cable == kRingReturnCable ? rig.segment.restore_ring_cable() : rig.segment.restore_link(cable)).ok());
}

struct PortResult {
  bool returned{false};
  std::uint16_t wkc{0};
  MasterPort back_on{MasterPort::main};
};

PortResult send_from(Rig& rig, MasterPort from, std::uint16_t station = 0) {
  rig.send_port = from;
  const auto r = station == 0 ? rig.read(Command::BRD, 0, reg::kType, 1) : rig.read(Command::FPRD, station, reg::kType, 1);
  rig.send_port = MasterPort::main;
  return PortResult{r.returned, r.wkc, rig.last_outcome.port};
}

TEST(RobotRing, ClosedRingProcessesEverySlaveOnceFromMainAndReturnsOnTheRingPort) {
  auto rig = ring_robot();
  const PortResult main = send_from(*rig, MasterPort::main);
  ASSERT_TRUE(main.returned);
  EXPECT_EQ(main.wkc, kSlaveCount);
  EXPECT_EQ(main.back_on, MasterPort::ring);
  const PortResult ring = send_from(*rig, MasterPort::ring);
  ASSERT_TRUE(ring.returned);
  EXPECT_EQ(ring.wkc, 0);
  EXPECT_EQ(ring.back_on, MasterPort::main);
  // The last slave's free port carries the ring cable: its link is up.
  const std::uint16_t dl = rig->read16(kSlaves[kRingReturnSlave].station_address, reg::kDlStatus);
  EXPECT_NE(dl & reg::dl_status_link(kRingReturnPort), 0);
}

TEST(RobotRing, KeepsTheTreesSlavesAndProcessingOrder) {
  auto rig = ring_robot();
  // Auto-increment position p is kSlaves[p] (the station addresses were assigned by position).
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    EXPECT_EQ(rig->read16(kSlaves[p].station_address, reg::kStationAddress), kSlaves[p].station_address) << kSlaves[p].name;
  }
  // Every cable lies on the line: each slave's upstream is the one before it.
  for (std::size_t p = 1; p < kSlaveCount; ++p) EXPECT_EQ(kRingCabling[p].upstream, p - 1);
}

TEST(RobotRing, EverySingleCutLosesNoSlaveAndEachFrameComesBackOnItsOwnPort) {
  auto rig = ring_robot();
  for (std::size_t cable = 0; cable < kCableCount; ++cable) {
    cut(*rig, cable);
    const PortResult main = send_from(*rig, MasterPort::main);
    const PortResult ring = send_from(*rig, MasterPort::ring);
    const std::uint16_t main_wkc = main.returned ? main.wkc : 0;
    const std::uint16_t ring_wkc = ring.returned ? ring.wkc : 0;
    EXPECT_EQ(main_wkc + ring_wkc, kSlaveCount) << "cable " << cable;
    // The slaves before the cut answer on main, the ones after it on ring.
    const std::size_t before = cable;  // cable k is between position k - 1 and k
    EXPECT_EQ(main_wkc, before) << "cable " << cable;
    if (cable > 0) {  // cable 0 is the master's main cable: nothing comes back on main
      EXPECT_TRUE(main.returned) << "cable " << cable;
      EXPECT_EQ(main.back_on, MasterPort::main) << "cable " << cable;
    }
    if (cable < kRingReturnCable) {
      EXPECT_TRUE(ring.returned) << "cable " << cable;
      EXPECT_EQ(ring.back_on, MasterPort::ring) << "cable " << cable;
    }
    // Each slave by its station address: exactly one of the two frames reaches it.
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      const PortResult m = send_from(*rig, MasterPort::main, kSlaves[p].station_address);
      const PortResult r = send_from(*rig, MasterPort::ring, kSlaves[p].station_address);
      EXPECT_EQ((m.returned ? m.wkc : 0) + (r.returned ? r.wkc : 0), 1) << "cable " << cable << ", " << kSlaves[p].name;
    }
    restore(*rig, cable);
    const PortResult whole = send_from(*rig, MasterPort::main);
    EXPECT_EQ(whole.wkc, kSlaveCount) << "restored cable " << cable;
    EXPECT_EQ(whole.back_on, MasterPort::ring) << "restored cable " << cable;
  }
}

TEST(RobotRing, TwoCutsLoseExactlyTheSlavesBetweenThem) {
  auto rig = ring_robot();
  for (std::size_t first = 0; first < kCableCount; ++first) {  // every pair of cables
    for (std::size_t second = first + 1; second < kCableCount; ++second) {
      cut(*rig, first);
      cut(*rig, second);
      for (std::size_t p = 0; p < kSlaveCount; ++p) {
        const PortResult m = send_from(*rig, MasterPort::main, kSlaves[p].station_address);
        const PortResult r = send_from(*rig, MasterPort::ring, kSlaves[p].station_address);
        const bool between = p >= first && p < second;
        EXPECT_EQ((m.returned ? m.wkc : 0) + (r.returned ? r.wkc : 0), between ? 0 : 1)
            << "cuts " << first << " and " << second << ", " << kSlaves[p].name;
      }
      const PortResult main = send_from(*rig, MasterPort::main);
      const PortResult ring = send_from(*rig, MasterPort::ring);
      EXPECT_EQ((main.returned ? main.wkc : 0) + (ring.returned ? ring.wkc : 0), kSlaveCount - (second - first))
          << "cuts " << first << " and " << second;
      restore(*rig, first);
      restore(*rig, second);
      const PortResult whole = send_from(*rig, MasterPort::main);
      EXPECT_EQ(whole.wkc, kSlaveCount) << "restored " << first << " and " << second;
      EXPECT_EQ(whole.back_on, MasterPort::ring);
    }
  }
}

TEST(RobotRing, APowerCycledSlaveIsLostAloneAndComesBackInInit) {
  auto rig = ring_robot();
  const std::size_t victim = slave_position_of_joint(joint_index_by_name("l_leg"));
  ASSERT_TRUE(rig->segment.set_power(victim, false, rig->now).ok());
  const PortResult main = send_from(*rig, MasterPort::main);
  const PortResult ring = send_from(*rig, MasterPort::ring);
  EXPECT_EQ(main.wkc + ring.wkc, kSlaveCount - 1);
  EXPECT_EQ(main.back_on, MasterPort::main);
  EXPECT_EQ(ring.back_on, MasterPort::ring);
  ASSERT_TRUE(rig->segment.set_power(victim, true, rig->now).ok());
  EXPECT_EQ(send_from(*rig, MasterPort::main).wkc, kSlaveCount);
}

}  // namespace
}  // namespace rescue::drivers::testing
