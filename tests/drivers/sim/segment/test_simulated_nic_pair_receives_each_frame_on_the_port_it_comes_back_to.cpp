// The simulated robot in its ring configuration behind two loopback NICs (the master's main and
// ring ports) on one virtual clock: a frame sent on main with the ring closed is processed by all 23
// slaves and received on the ring NIC; with a cut each NIC gets its own frame back, processed by the
// slaves on its side; the frame path allocates nothing; a ring pair on a tree robot is refused.
#include <cstdio>
#include <memory>

#include "core/memory/heap_guard.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

class NicPair : public ::testing::Test {
 protected:
  void SetUp() override {
    RobotSegmentOptions options;
    options.ring = true;
    robot = std::make_unique<SimulatedRobot>(options, clock.now());
    ASSERT_TRUE(robot->status().ok());
    nics = std::make_unique<SimulatedNicPair>(robot->segment(), clock);
    ASSERT_TRUE(nics->status().ok());
  }
  // Sends a broadcast read on `nic`; the working counter received on `on` (-1: none before 1 ms).
  int received_wkc(hal::Nic& on) {
    const auto got = on.receive(ByteSpan(buffer), clock.now() + hal::kNsPerMs);
    if (!got.ok()) return -1;
    auto view = ecat::FrameView::parse(ConstByteSpan(buffer.data(), got.value()));
    EXPECT_TRUE(view.ok());
    return (*view.value().begin()).wkc();
  }
  void send(hal::Nic& nic, std::uint8_t index) {
    const auto frame = brd_frame(index);
    ASSERT_TRUE(nic.send(ConstByteSpan(frame.data(), frame.size())).ok());
  }

  hal::VirtualClock clock{1'000'000};
  std::unique_ptr<SimulatedRobot> robot;
  std::unique_ptr<SimulatedNicPair> nics;
  std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
};

TEST_F(NicPair, ClosedRingSendsMainsFrameToTheRingNic) {
  const hal::Nanoseconds sent = clock.now();
  send(nics->main(), 1);
  EXPECT_EQ(received_wkc(nics->ring()), static_cast<int>(kSlaveCount));
  const hal::Nanoseconds main_to_ring = clock.now() - sent;
  EXPECT_EQ(received_wkc(nics->main()), -1);
  const hal::Nanoseconds sent_ring = clock.now();
  send(nics->ring(), 2);
  EXPECT_EQ(received_wkc(nics->main()), 0);  // round the ring the other way, unprocessed
  const hal::Nanoseconds ring_to_main = clock.now() - sent_ring;
  std::printf("ring: a 60-byte frame main -> ring port through 23 slaves: %lld ns; ring -> main port: %lld ns\n",
              static_cast<long long>(main_to_ring), static_cast<long long>(ring_to_main));
  // Each cable once instead of twice: well under the tree's round trip (tens of microseconds).
  EXPECT_LT(main_to_ring, 40 * hal::kNsPerUs);
  EXPECT_EQ(nics->main().stats().frames_sent, 1u);
  EXPECT_EQ(nics->ring().stats().frames_received, 1u);
  EXPECT_STREQ(nics->ring().name(), "sim-ring");
}

TEST_F(NicPair, ACutGivesEachNicItsOwnFrameBack) {
  const std::size_t cut_at = slave_position_of_joint(joint_index_by_name("l_leg"));
  ASSERT_TRUE(robot->segment().cut_link(cut_at).ok());
  send(nics->main(), 1);
  send(nics->ring(), 2);
  const int main_wkc = received_wkc(nics->main());
  const int ring_wkc = received_wkc(nics->ring());
  EXPECT_EQ(main_wkc, static_cast<int>(cut_at));
  EXPECT_EQ(main_wkc + ring_wkc, static_cast<int>(kSlaveCount));
}

TEST_F(NicPair, TheFramePathAllocatesNothing) {
  const auto frame = brd_frame(3);
  const ConstByteSpan bytes(frame.data(), frame.size());
  int received = 0;
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::count);
  for (std::size_t cable = 0; cable < kSlaveCount; ++cable) {
    (void)robot->segment().cut_link(cable);
    (void)nics->main().send(bytes);
    (void)nics->ring().send(bytes);
    received += received_wkc(nics->main()) + received_wkc(nics->ring());
    (void)robot->segment().restore_link(cable);
  }
  const HeapGuardCounters heap = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(heap.allocations, 0U);
  // Cable 0 is main's own: its frame is lost (-1); every other cut: 23 between the two ports.
  EXPECT_EQ(received, static_cast<int>(kSlaveCount * kSlaveCount) - 1);
}

TEST(NicPairOnATree, IsRefused) {
  hal::VirtualClock clock{0};
  auto tree = std::make_unique<SimulatedRobot>();
  ASSERT_TRUE(tree->status().ok());
  SimulatedNicPair nics(tree->segment(), clock);
  ASSERT_FALSE(nics.status().ok());
  EXPECT_STREQ(nics.status().error().what, "ring NICs on a segment without a ring cable");
}

TEST(RingRobot, RefusesTheSpareSlave) {
  RobotSegmentOptions options;
  options.ring = true;
  options.spare_slave = true;
  auto robot = std::make_unique<SimulatedRobot>(options);
  ASSERT_FALSE(robot->status().ok());
}

}  // namespace
}  // namespace rescue::drivers::testing
