// A frame the host reads late (over veth on a loaded host: the simulator's poll timed out, its idle
// step advanced every clock to the time it woke, and only then the frame that had arrived meanwhile
// was read) must not be walked at its arrival, in the segment's past: every ESC's clock would read
// its last advance, the same instant for all, and each slave's compare of the reference's time
// (FRMW of 0x0910) would see its whole propagation delay as a clock error (seen over veth: 0x092C of
// 1182 ns and 4458 ns for one frame, the clocks steered by 1/16 of it). It enters at the instant the
// segment has reached, as one late frame, and is counted.
#include <cstdio>

#include "tests/support/dc_master_steps.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr hal::Nanoseconds kCycle = hal::kNsPerMs;
constexpr std::uint64_t kMasterTime = 0x0123'4567'89AB'CDEFULL;
constexpr hal::Nanoseconds kReadLate = 300 * hal::kNsPerUs;  // how far the idle step ran past the arrival

std::unique_ptr<Rig> clocks_in_step() {
  RobotSegmentOptions options;
  options.seed = 7;
  auto rig = Rig::robot(options);
  prepare_distributed_clocks(*rig, kMasterTime, true);
  for (int cycle = 0; cycle < 6000; ++cycle) distribute_reference_time(*rig, kCycle);
  return rig;
}

TEST(FrameReadLate, EntersAtTheSegmentsTimeSoEverySlaveComparesTheReferenceAtOneTrueInstant) {
  auto rig = clocks_in_step();
  ASSERT_LE(worst_sync_error(*rig, rig->now), 5) << "the clocks are in step before the late frame";
  ASSERT_LE(worst_reported_difference(*rig), 5);
  EXPECT_EQ(rig->segment.counters().taken_late, 0U) << "frames sent in order are never late";

  // The frame arrived at `arrived`; the host advanced the segment past it before reading it.
  const hal::Nanoseconds arrived = rig->now;
  rig->segment.advance_to(arrived + kReadLate);
  distribute_reference_time(*rig, kCycle);  // sent at `arrived`
  const std::int64_t difference = worst_reported_difference(*rig);
  std::printf("a frame read %lld us late: max |0x092C| %lld ns\n", static_cast<long long>(kReadLate / hal::kNsPerUs),
              static_cast<long long>(difference));
  EXPECT_EQ(rig->segment.counters().taken_late, 1U);
  EXPECT_LE(difference, 5) << "a slave compared the reference's time of another instant";

  // And no clock was steered off by it.
  std::int64_t worst = 0;
  for (int cycle = 0; cycle < 100; ++cycle) {
    distribute_reference_time(*rig, kCycle);
    worst = std::max(worst, worst_sync_error(*rig, rig->now));
  }
  EXPECT_LE(worst, 5);
  EXPECT_EQ(rig->segment.counters().taken_late, 1U);
}

// A segment built again (a simulator session restarted on a fresh clock, a test's second robot on
// one segment) starts at the time it is built at: its first frames are not late against the
// instant the old build had reached, and its clocks run from the new start, not from the old one.
TEST(FrameReadLate, ASegmentBuiltAgainAtAnEarlierTimeTakesItsFirstFramesAtTheirOwnTime) {
  auto rig = Rig::single();
  constexpr hal::Nanoseconds kOldSession = 5 * hal::kNsPerMs * 1000;  // 5 s
  rig->wait(kOldSession);
  SegmentSlave s;
  s.name = "single";
  s.esc = joint_esc_config();
  s.link_delay_ns = kPhyPairDelayNs;
  s.device = &rig->device();
  ASSERT_TRUE(rig->segment.build(Span<const SegmentSlave>(&s, 1), 0).ok());
  rig->now = 0;

  const DatagramResult time = rig->read(Command::APRD, 0, reg::kDcSystemTime, 8);
  ASSERT_TRUE(time.returned);
  ASSERT_EQ(time.data.size(), 8U);
  std::uint64_t local = 0;
  for (std::size_t i = 0; i < 8; ++i) local |= static_cast<std::uint64_t>(time.data[i]) << (8 * i);
  std::printf("first frame of the new build: 0x0910 reads %llu ns\n", static_cast<unsigned long long>(local));
  EXPECT_EQ(rig->segment.counters().taken_late, 0U) << "a frame of the new build was taken at the old build's time";
  EXPECT_LT(local, static_cast<std::uint64_t>(hal::kNsPerMs)) << "the clock ran on from the old build's instant";
}

}  // namespace
}  // namespace rescue::drivers::testing
