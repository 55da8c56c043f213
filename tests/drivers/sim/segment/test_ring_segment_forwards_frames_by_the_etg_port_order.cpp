// A segment with a ring cable walks every frame by the ETG forwarding rule: in on port N, out by the
// next open port in the order 0 -> 3 -> 1 -> 2 -> 0, processed only behind port 0's receive side.
// With the ring closed a frame from the main port is processed by every slave once and comes back on
// the ring port, one from the ring port passes unprocessed back to main; a cut splits the slaves
// between the two ports; delays are per direction; bad ring cables are refused.
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr hal::Nanoseconds kLink = 300;
constexpr hal::Nanoseconds kRingLink = 700;

// Three two-port slaves in a line (0:1 -> 1:0, 1:1 -> 2:0); the ring cable onto slave 2's port 1.
std::unique_ptr<Rig> line_of_three(const RingCable& ring, Status* built = nullptr) {
  auto rig = std::make_unique<Rig>();
  std::array<SegmentSlave, 3> slaves{};
  for (std::size_t p = 0; p < slaves.size(); ++p) {
    rig->devices.push_back(std::make_unique<TestDevice>(static_cast<std::uint16_t>(0x100 + p)));
    SegmentSlave& s = slaves[p];
    s.name = p == 0 ? "first" : (p == 1 ? "middle" : "last");
    s.esc = joint_esc_config();
    s.upstream = p == 0 ? kUpstreamIsMaster : static_cast<std::uint8_t>(p - 1);
    s.upstream_port = p == 0 ? 0 : 1;
    s.link_delay_ns = kLink;
    s.return_skew_ns = static_cast<hal::Nanoseconds>(10 * (p + 1));
    s.device = rig->devices.back().get();
  }
  const Status st = rig->segment.build_ring(Span<const SegmentSlave>(slaves), ring, 0);
  if (built != nullptr) *built = st;
  return rig;
}

RingCable ring_onto_last() { return RingCable{2, 1, kRingLink, 40}; }

TEST(RingSegment, ClosedRingFromMainIsProcessedByEverySlaveOnceAndComesBackOnTheRingPort) {
  auto rig = line_of_three(ring_onto_last());
  const auto brd = rig->read(Command::BRD, 0, reg::kType, 1);
  ASSERT_TRUE(brd.returned);
  EXPECT_EQ(brd.wkc, 3);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::ring);
  // Auto-increment order is the line's: position 2 is "last".
  rig->assign_station_addresses();
  EXPECT_EQ(rig->read16(0x1002, reg::kStationAddress), 0x1002);
  EXPECT_EQ(rig->read(Command::FPRD, 0x1002, reg::kType, 1).wkc, 1);
}

TEST(RingSegment, ClosedRingFromTheRingPortPassesUnprocessedBackToMain) {
  auto rig = line_of_three(ring_onto_last());
  rig->send_port = MasterPort::ring;
  const auto brd = rig->read(Command::BRD, 0, reg::kType, 1);
  ASSERT_TRUE(brd.returned);
  EXPECT_EQ(brd.wkc, 0);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::main);
}

TEST(RingSegment, DelaysAddUpPerDirection) {
  auto rig = line_of_three(ring_onto_last());
  std::array<hal::Nanoseconds, 3> processing{};
  std::array<hal::Nanoseconds, 3> forwarding{};
  for (std::size_t p = 0; p < 3; ++p) {
    processing[p] = rig->segment.slave(p).esc.processing_delay_ns;
    forwarding[p] = rig->segment.slave(p).esc.forwarding_delay_ns;
  }
  const hal::Nanoseconds sent = rig->now;
  ASSERT_TRUE(rig->read(Command::BRD, 0, reg::kType, 1).returned);
  // Main -> ring: every cable away from the master, each slave's processing unit, the ring cable back.
  EXPECT_EQ(rig->last_outcome.first_bit_back - sent, 3 * kLink + processing[0] + processing[1] + processing[2] + kRingLink + 40);

  rig->send_port = MasterPort::ring;
  const hal::Nanoseconds sent_ring = rig->now;
  ASSERT_TRUE(rig->read(Command::BRD, 0, reg::kType, 1).returned);
  // Ring -> main: the ring cable away from the master, every cable towards it (with its skew), forwarding only.
  EXPECT_EQ(rig->last_outcome.first_bit_back - sent_ring,
            kRingLink + 3 * kLink + 10 + 20 + 30 + forwarding[0] + forwarding[1] + forwarding[2]);
}

TEST(RingSegment, ACutSplitsTheSlavesBetweenThePortsEachFrameBackOnItsOwn) {
  auto rig = line_of_three(ring_onto_last());
  ASSERT_TRUE(rig->segment.cut_link(1).ok());  // between "first" and "middle"
  const auto main = rig->read(Command::BRD, 0, reg::kType, 1);
  ASSERT_TRUE(main.returned);
  EXPECT_EQ(main.wkc, 1);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::main);

  rig->send_port = MasterPort::ring;
  const auto ring = rig->read(Command::BRD, 0, reg::kType, 1);
  ASSERT_TRUE(ring.returned);
  EXPECT_EQ(ring.wkc, 2);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::ring);
  // The ring's frame is processed on its way back from the break: "middle" (beside it) comes first.
  const auto first_from_ring = rig->read(Command::APRD, 0, reg::kStationAlias, 2);
  EXPECT_EQ(first_from_ring.wkc, 1);
  EXPECT_EQ(from_le(first_from_ring.data), 0x101u);

  ASSERT_TRUE(rig->segment.restore_link(1).ok());
  rig->send_port = MasterPort::main;
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, 3);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::ring);
}

TEST(RingSegment, ACutRingCableMakesItATreeAgain) {
  auto rig = line_of_three(ring_onto_last());
  ASSERT_TRUE(rig->segment.cut_ring_cable().ok());
  EXPECT_TRUE(rig->segment.ring_cable_cut());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, 3);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::main);
  rig->send_port = MasterPort::ring;
  EXPECT_FALSE(rig->read(Command::BRD, 0, reg::kType, 1).returned);
  EXPECT_EQ(rig->segment.counters().lost_no_link, 1u);
  ASSERT_TRUE(rig->segment.restore_ring_cable().ok());
  EXPECT_EQ(rig->read(Command::BRD, 0, reg::kType, 1).wkc, 0);
  EXPECT_EQ(rig->last_outcome.port, MasterPort::main);
}

TEST(RingSegment, AnEscWithEveryPortClosedKeepsTheFrameAndItIsCountedLost) {
  auto rig = line_of_three(ring_onto_last());
  rig->assign_station_addresses();
  // "middle": every port's loop forced closed (DL control loop bits 11), port 0 included.
  std::uint32_t closed = 0x00070000;  // the other DL control bits as the robot's tests write them
  for (unsigned port = 0; port < kMaxEscPorts; ++port) closed |= 3U << reg::dl_control_loop_shift(port);
  EXPECT_EQ(rig->write(Command::FPWR, 0x1001, reg::kDlControl, le32(closed)).wkc, 1);
  // A frame from the ring port now enters "last", goes on to "middle" and never leaves it.
  rig->send_port = MasterPort::ring;
  EXPECT_FALSE(rig->read(Command::BRD, 0, reg::kType, 1).returned);
  EXPECT_EQ(rig->segment.counters().lost_circulating, 1u);
}

TEST(RingSegment, BadRingCablesAreRefusedAndNothingIsBuilt) {
  Status st;
  auto cabled = line_of_three(RingCable{1, 1, kRingLink, 0}, &st);  // "last" hangs off middle's port 1
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, Errc::invalid_argument);
  EXPECT_STREQ(st.error().what, "ring cable onto a port already cabled");
  EXPECT_EQ(cabled->segment.slave_count(), 0u);
  EXPECT_FALSE(cabled->segment.has_ring());

  auto port0 = line_of_three(RingCable{2, 0, kRingLink, 0}, &st);
  ASSERT_FALSE(st.ok());
  EXPECT_STREQ(st.error().what, "ring cable onto port 0 or a port the ESC lacks");
  auto port3 = line_of_three(RingCable{2, 3, kRingLink, 0}, &st);  // two-port ESC
  ASSERT_FALSE(st.ok());
  auto nobody = line_of_three(RingCable{3, 1, kRingLink, 0}, &st);
  ASSERT_FALSE(st.ok());
  EXPECT_STREQ(st.error().what, "ring cable onto no slave");
}

TEST(RingSegment, TheRingPortOfATreeIsRefused) {
  auto rig = Rig::robot();
  std::array<std::uint8_t, 64> frame{};
  const auto outcome = rig->segment.process(ByteSpan(frame.data(), frame.size()), 0, MasterPort::ring);
  ASSERT_FALSE(outcome.ok());
  EXPECT_STREQ(outcome.error().what, "ring port used on a segment without a ring cable");
  EXPECT_FALSE(rig->segment.cut_ring_cable().ok());
  EXPECT_EQ(rig->segment.counters().frames, 0u);
}

}  // namespace
}  // namespace rescue::drivers::testing
