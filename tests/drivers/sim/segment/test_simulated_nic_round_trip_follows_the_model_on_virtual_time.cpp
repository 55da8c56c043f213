// The loopback NIC gives a frame back after the round trip the model predicts (cables, PHYs, every
// ESC's forwarding delays, the frame's own length at 100 Mbit/s), moving only virtual time.
#include <cstdio>

#include "drivers/sim/segment/simulated_nic.hpp"
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

// Round trip of a frame's start through the whole tree: every cable twice, every ESC's processing
// delay once and its forwarding delay once per branch it sends the frame down.
hal::Nanoseconds model_round_trip(const SimulatedSegment& segment) {
  hal::Nanoseconds total = 0;
  for (std::size_t p = 0; p < segment.slave_count(); ++p) {
    const SegmentSlave& s = segment.slave(p);
    total += 2 * s.link_delay_ns + s.esc.processing_delay_ns;
    for (unsigned port = 1; port < kMaxEscPorts; ++port) {
      if (segment.child(p, port) != kUpstreamIsMaster) total += s.esc.forwarding_delay_ns;
    }
  }
  return total;
}

class NicRoundTrip : public ::testing::Test {
 protected:
  void SetUp() override { rig = Rig::robot(); }
  std::unique_ptr<Rig> rig;
  hal::VirtualClock clock{1'000'000};
  std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
};

TEST_F(NicRoundTrip, FrameComesBackAfterTheModelledDelay) {
  SimulatedNic nic(rig->segment, clock);
  const auto frame = brd_frame(1);
  ASSERT_TRUE(nic.send(ConstByteSpan(frame.data(), frame.size())).ok());
  const auto got = nic.receive(ByteSpan(buffer), clock.now() + hal::kNsPerMs);
  ASSERT_TRUE(got.ok());
  ASSERT_EQ(got.value(), frame.size());
  const hal::Nanoseconds wire = static_cast<hal::Nanoseconds>(frame.size() + kWireOverheadBytes) * kNsPerByte;
  EXPECT_EQ(clock.now() - 1'000'000, model_round_trip(rig->segment) + wire);
  std::printf("nic: a 60-byte frame through the robot's 23 slaves comes back after %lld ns (%lld ns of it its own length)\n",
              static_cast<long long>(clock.now() - 1'000'000), static_cast<long long>(wire));
  // About 1 us per joint with 100BASE-TX ports: 23 slaves give a round trip of tens of microseconds.
  EXPECT_GT(clock.now() - 1'000'000, 20 * hal::kNsPerUs);
  EXPECT_LT(clock.now() - 1'000'000, 60 * hal::kNsPerUs);
  auto view = ecat::FrameView::parse(ConstByteSpan(buffer.data(), got.value()));
  ASSERT_TRUE(view.ok());
  EXPECT_EQ((*view.value().begin()).wkc(), kSlaveCount);
  EXPECT_EQ(buffer[6] & 0x02, 0x02);  // source address marked by the ESCs
  EXPECT_EQ(nic.stats().frames_sent, 1u);
  EXPECT_EQ(nic.stats().frames_received, 1u);
}

TEST_F(NicRoundTrip, NothingToReceiveWaitsUntilTheDeadline) {
  SimulatedNic nic(rig->segment, clock);
  const auto got = nic.receive(ByteSpan(buffer), clock.now() + 250 * hal::kNsPerUs);
  ASSERT_FALSE(got.ok());
  EXPECT_EQ(got.error().code, Errc::timeout);
  EXPECT_EQ(clock.now(), 1'250'000);
  EXPECT_EQ(nic.stats().receive_timeouts, 1u);
}

TEST_F(NicRoundTrip, AFrameStillOnItsWayIsNotDeliveredBeforeItArrives) {
  SimulatedNic nic(rig->segment, clock);
  const auto frame = brd_frame(2);
  ASSERT_TRUE(nic.send(ConstByteSpan(frame.data(), frame.size())).ok());
  EXPECT_FALSE(nic.receive(ByteSpan(buffer), clock.now() + 5 * hal::kNsPerUs).ok());
  EXPECT_TRUE(nic.receive(ByteSpan(buffer), clock.now() + hal::kNsPerMs).ok());
}

TEST_F(NicRoundTrip, BackToBackFramesShareTheWireAndArriveInOrder) {
  SimulatedNic nic(rig->segment, clock);
  const auto first = brd_frame(10);
  const auto second = brd_frame(11);
  ASSERT_TRUE(nic.send(ConstByteSpan(first.data(), first.size())).ok());
  ASSERT_TRUE(nic.send(ConstByteSpan(second.data(), second.size())).ok());
  ASSERT_TRUE(nic.receive(ByteSpan(buffer), clock.now() + hal::kNsPerMs).ok());
  EXPECT_EQ(buffer[ecat::kEthernetHeaderSize + 2 + 1], 10);
  const hal::Nanoseconds first_back = clock.now();
  ASSERT_TRUE(nic.receive(ByteSpan(buffer), clock.now() + hal::kNsPerMs).ok());
  EXPECT_EQ(buffer[ecat::kEthernetHeaderSize + 2 + 1], 11);
  // The second frame left after the first one's last bit and the inter-frame gap.
  EXPECT_EQ(clock.now() - first_back,
            static_cast<hal::Nanoseconds>(first.size() + kWireOverheadBytes + kInterFrameGapBytes) * kNsPerByte);
}

TEST_F(NicRoundTrip, DroppedFrameNeverArrives) {
  SimulatedNic nic(rig->segment, clock);
  rig->segment.drop_frames(1);
  const auto frame = brd_frame(3);
  ASSERT_TRUE(nic.send(ConstByteSpan(frame.data(), frame.size())).ok());
  EXPECT_FALSE(nic.receive(ByteSpan(buffer), clock.now() + hal::kNsPerMs).ok());
  ASSERT_TRUE(nic.send(ConstByteSpan(frame.data(), frame.size())).ok());
  EXPECT_TRUE(nic.receive(ByteSpan(buffer), clock.now() + hal::kNsPerMs).ok());
}

TEST_F(NicRoundTrip, AMinuteOfCyclesRunsOnVirtualTimeInWellUnderAMinute) {
  // 1 kHz for 60 s of robot time (an hour is a benchmark's business): virtual time moves by
  // exactly the cycles, however long the host takes.
  SimulatedNic nic(rig->segment, clock);
  const auto frame = brd_frame(4);
  const hal::Nanoseconds start = clock.now();
  for (int cycle = 0; cycle < 60'000; ++cycle) {
    const hal::Nanoseconds period_start = start + static_cast<hal::Nanoseconds>(cycle) * hal::kNsPerMs;
    clock.sleep_until(period_start);
    ASSERT_TRUE(nic.send(ConstByteSpan(frame.data(), frame.size())).ok());
    ASSERT_TRUE(nic.receive(ByteSpan(buffer), period_start + 500 * hal::kNsPerUs).ok());
  }
  EXPECT_LT(clock.now() - start, 60 * hal::kNsPerSec);
  EXPECT_GT(clock.now() - start, 59 * hal::kNsPerSec);
  EXPECT_EQ(nic.stats().frames_received, 60'000u);
}

}  // namespace
}  // namespace rescue::drivers::testing
