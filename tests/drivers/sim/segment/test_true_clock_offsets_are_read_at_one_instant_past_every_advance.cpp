// The simulator's true clock offsets (what `sim`'s `clocks` prints, what the ring's side-by-side
// script and veth test take for SYNC0 moves) must be read at one instant that no ESC's clock has
// passed. A frame's walk advances each slave's clock to that frame's arrival there, so a far slave
// is ahead of the host's `now` by its propagation delay; read at `now` it was clamped to its last
// advance and looked microseconds ahead of the reference (seen over veth: positions 7 .. 22 of the
// ring 31 .. 7359 ns "ahead" for one sample while the clocks were in step).
#include <cstdio>

#include "tests/support/dc_master_steps.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr hal::Nanoseconds kCycle = hal::kNsPerMs;
constexpr std::uint64_t kMasterTime = 0x0123'4567'89AB'CDEFULL;

// Each slave's offset read at `at` one by one, as the console did before.
std::int64_t worst_offset_read_at(const Rig& rig, hal::Nanoseconds at) { return worst_sync_error(rig, at); }

std::int64_t worst(const std::array<std::int64_t, kMaxSegmentSlaves>& offsets, std::size_t count) {
  std::int64_t w = 0;
  for (std::size_t p = 0; p < count; ++p) w = std::max(w, offsets[p] < 0 ? -offsets[p] : offsets[p]);
  return w;
}

TEST(TrueClockOffsets, AreReadPastEveryClocksLastAdvanceSoAFrameInFlightMovesNone) {
  RobotSegmentOptions options;
  options.seed = 7;
  auto rig = Rig::robot(options);
  prepare_distributed_clocks(*rig, kMasterTime, true);
  for (int cycle = 0; cycle < 6000; ++cycle) distribute_reference_time(*rig, kCycle);
  ASSERT_LE(worst_sync_error(*rig, rig->now), 5) << "the clocks are in step before the frame";

  // One more frame, sent at `sent`: the host's `now` is still `sent` while the far slaves' clocks
  // were advanced to the frame's arrival there.
  const hal::Nanoseconds sent = rig->now;
  distribute_reference_time(*rig, kCycle);
  const std::int64_t naive = worst_offset_read_at(*rig, sent);
  std::array<std::int64_t, kMaxSegmentSlaves> offsets{};
  const hal::Nanoseconds at = rig->segment.true_clock_offsets(sent, Span<std::int64_t>(offsets));
  std::printf("read at the send instant: one by one %lld ns, at one instant %lld ns (%lld ns after the send)\n",
              static_cast<long long>(naive), static_cast<long long>(worst(offsets, rig->segment.slave_count())),
              static_cast<long long>(at - sent));
  EXPECT_GT(naive, 1000) << "the far slaves' clocks were advanced past the send instant (the artefact's cause)";
  EXPECT_GT(at, sent);
  EXPECT_LE(worst(offsets, rig->segment.slave_count()), 5);
  for (std::size_t p = 0; p < rig->segment.slave_count(); ++p) EXPECT_GE(at, rig->segment.esc(p).dc().clock().advanced_to());

  // Asked at an instant past every advance, the one-instant read is the plain read.
  const hal::Nanoseconds later = rig->now;
  (void)rig->segment.true_clock_offsets(later, Span<std::int64_t>(offsets));
  EXPECT_EQ(worst(offsets, rig->segment.slave_count()), worst_sync_error(*rig, later));
  EXPECT_EQ(offsets[0], 0);
}

}  // namespace
}  // namespace rescue::drivers::testing
