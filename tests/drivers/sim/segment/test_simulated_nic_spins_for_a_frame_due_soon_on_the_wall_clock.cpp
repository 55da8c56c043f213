// With a receive spin, the loopback NIC on the wall clock waits for a frame due back within the spin
// by reading the clock rather than sleeping (a few microseconds of sleep cost a whole wake-up), and
// still never hands a frame back before the model's round trip. On a virtual clock, which does not
// move by itself, the same NIC falls back to sleep_until, which moves it: it never hangs.
#include <array>
#include <cstdint>
#include <vector>

#include "drivers/sim/segment/simulated_nic.hpp"
#include "hal/time/clock.hpp"
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

TEST(SimulatedNicSpin, OnTheWallClockAFrameComesBackNoEarlierThanTheModelSays) {
  auto rig = Rig::robot();
  hal::MonotonicClock wall;
  SimulatedNic nic(rig->segment, wall, 150 * hal::kNsPerUs);
  std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
  // The model's round trip of this frame, measured on virtual time with the same segment model.
  auto virtual_rig = Rig::robot();
  hal::VirtualClock virtual_clock{hal::kNsPerSec};
  SimulatedNic model(virtual_rig->segment, virtual_clock);
  const auto frame = brd_frame(1);
  ASSERT_TRUE(model.send(ConstByteSpan(frame.data(), frame.size())).ok());
  ASSERT_TRUE(model.receive(ByteSpan(buffer), virtual_clock.now() + hal::kNsPerMs).ok());
  const hal::Nanoseconds round_trip = virtual_clock.now() - hal::kNsPerSec;

  for (std::uint8_t i = 0; i < 50; ++i) {
    const auto f = brd_frame(i);
    const hal::Nanoseconds sent = wall.now();
    ASSERT_TRUE(nic.send(ConstByteSpan(f.data(), f.size())).ok());
    const auto got = nic.receive(ByteSpan(buffer), wall.now() + 100 * hal::kNsPerMs);
    ASSERT_TRUE(got.ok()) << "frame " << int{i};
    EXPECT_GE(wall.now() - sent, round_trip) << "frame " << int{i} << " came back before its round trip";
    auto view = ecat::FrameView::parse(ConstByteSpan(buffer.data(), got.value()));
    ASSERT_TRUE(view.ok());
    EXPECT_EQ((*view.value().begin()).wkc(), kSlaveCount);
  }
  EXPECT_EQ(nic.stats().frames_received, 50U);
}

TEST(SimulatedNicSpin, OnAVirtualClockASpinFallsBackToSleepingAndNeverHangs) {
  auto rig = Rig::robot();
  hal::VirtualClock clock{hal::kNsPerSec};
  SimulatedNic nic(rig->segment, clock, 150 * hal::kNsPerUs);
  std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
  const auto frame = brd_frame(1);
  ASSERT_TRUE(nic.send(ConstByteSpan(frame.data(), frame.size())).ok());
  const auto got = nic.receive(ByteSpan(buffer), clock.now() + hal::kNsPerMs);
  ASSERT_TRUE(got.ok());
  EXPECT_GT(clock.now(), hal::kNsPerSec) << "the virtual clock was moved to the frame's return";
}

}  // namespace
}  // namespace rescue::drivers::testing
