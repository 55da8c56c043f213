// DC across a break when the master's ring copy leaves later than its main copy by a time that
// changes from frame to frame (a host that holds the master up between its two sends: over veth
// tens to hundreds of microseconds, docs/redundancy.md "DC across a break over veth"). The ring
// port notes when it sends and moves each ring-side time write to that instant (StampedPort,
// RingDcService::before_ring_send), R counts from when the read's copy was sent, and the leads
// leave out the latch frame's spacing: so the clocks behind the break keep issue 34's bounds
// (max |0x092C| at most 100 ns from 100 ms after the cut, no drive's SYNC0 edge moved by more than
// 1 us), with the reference before the break (the cable into r_track) and behind it (the master's
// main cable). Virtual time: the main port advances the clock after each send by 0..300 us.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <memory>

#include "drivers/joint/joint_bus.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "ecat/codec/registers.hpp"
#include "hal/time/clock.hpp"
#include "tests/support/ring_robot_rig.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

constexpr int kCyclesWithin = 100;  // 100 ms at the 1 ms period
constexpr int kCyclesOfBreak = 300;
constexpr std::uint32_t kBreakDifferenceBoundNs = 100;
constexpr std::int64_t kSync0MoveBoundNs = 1000;
constexpr hal::Nanoseconds kMaxHold = 300 * hal::kNsPerUs;

// The main port: after each frame it sends, the master is held up for a pseudo-random 0..300 us
// before it sends the ring copy.
class HeldAfterSend final : public hal::Nic {
 public:
  HeldAfterSend(drivers::SimulatedNic& inner, hal::VirtualClock& clock) noexcept : inner_(inner), clock_(clock) {}
  bool holding{false};

  Status send(ConstByteSpan frame) noexcept override {
    const Status sent = inner_.send(frame);
    if (holding) {
      state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
      clock_.advance(static_cast<hal::Nanoseconds>((state_ >> 33) % static_cast<std::uint64_t>(kMaxHold)));
    }
    return sent;
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    return inner_.receive(buffer, deadline);
  }
  hal::Clock& clock() noexcept override { return inner_.clock(); }
  const char* name() const noexcept override { return inner_.name(); }
  hal::NicStats stats() const noexcept override { return inner_.stats(); }

 private:
  drivers::SimulatedNic& inner_;
  hal::VirtualClock& clock_;
  std::uint64_t state_{1};
};

struct HeldRing {
  hal::VirtualClock clock{hal::kNsPerSec};
  drivers::SimulatedRobot robot{testing::ring_robot_options(), clock.now()};
  drivers::SimulatedNicPair nics{robot.segment(), clock};
  HeldAfterSend main{nics.main(), clock};
  drivers::JointBus bus{main, drivers::kRobotRingNetworkPlan};
  drivers::JointReferences references{};
  drivers::JointFeedback feedback{};

  void cycle() {
    clock.sleep_until(bus.next_wakeup());
    (void)bus.cycle(references, feedback);
  }
  // Slave p's system time minus the reference's (position 0) now: where its SYNC0 edge sits.
  std::int64_t offset(std::size_t p) {
    const hal::Nanoseconds now = clock.now();
    return static_cast<std::int64_t>(robot.segment().esc(p).system_time_at(now) - robot.segment().esc(0).system_time_at(now));
  }
};

struct BreakFigures {
  std::uint32_t difference{0};  // max |0x092C| behind the break from 100 ms after the cut
  std::int64_t sync0_moved{0};  // largest move of a drive's SYNC0 edge from the cut on
  SlaveMask written{0};
};

BreakFigures hold_and_cut(std::size_t cable) {
  auto rig = std::make_unique<HeldRing>();
  rig->bus.master().use_ring(rig->nics.ring());
  EXPECT_TRUE(rig->bus.bring_up(testing::fast_options()).ok()) << testing::describe_master_failure(rig->bus.master());
  for (int i = 0; i < 300; ++i) rig->cycle();
  EXPECT_EQ(rig->bus.master().state(), MasterState::op);
  rig->main.holding = true;
  for (int i = 0; i < 100; ++i) rig->cycle();  // with the ring closed nothing is written: the loops as before
  std::array<std::int64_t, kSlaveCount> before{};
  for (std::size_t p = 0; p < kSlaveCount; ++p) before[p] = rig->offset(p);
  EXPECT_TRUE(rig->robot.segment().cut_link(cable).ok());
  BreakFigures f;
  for (int i = 0; i < kCyclesOfBreak; ++i) {
    rig->cycle();
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if (kSlaves[p].kind == SlaveKind::joint_drive) f.sync0_moved = std::max(f.sync0_moved, std::abs(rig->offset(p) - before[p]));
      if (i < kCyclesWithin || p < cable) continue;
      const std::uint32_t raw = rig->robot.segment().esc(p).register_u32(reg::kDcSystemTimeDifference);
      f.difference = std::max(f.difference, raw & 0x7FFFFFFFU);
    }
  }
  f.written = rig->bus.master().ring_dc_status().written;
  std::printf("cable %zu, master held 0..300 us between its two sends: after break max |0x092C| %u ns behind it, "
              "SYNC0 moved %lld ns\n",
              cable, f.difference, static_cast<long long>(f.sync0_moved));
  return f;
}

TEST(RingDcSendStamps, TheClocksBehindABreakKeepTheirBoundsWhenTheRingCopyLeavesLate) {
  const BreakFigures f = hold_and_cut(12);  // into r_track: 11 DC slaves behind it, the reference before
  EXPECT_NE(f.written, 0U);
  EXPECT_LE(f.difference, kBreakDifferenceBoundNs);
  EXPECT_LE(f.sync0_moved, kSync0MoveBoundNs);
}

TEST(RingDcSendStamps, TheClocksKeepTheirBoundsWithTheReferenceBehindTheBreak) {
  const BreakFigures f = hold_and_cut(0);  // the master's main cable: all slaves on the ring side
  EXPECT_NE(f.written, 0U);
  EXPECT_LE(f.difference, kBreakDifferenceBoundNs);
  EXPECT_LE(f.sync0_moved, kSync0MoveBoundNs);
}

}  // namespace
}  // namespace rescue::ecat
