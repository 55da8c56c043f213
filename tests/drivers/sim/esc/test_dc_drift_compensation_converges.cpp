// With offsets and delays written and the reference time distributed every millisecond (FRMW of
// 0x0910), every slave's clock locks onto the reference despite crystal drifts of up to +-100 ppm:
// the slaves' own difference register 0x092C and their true system times converge to a few
// nanoseconds within a few thousand cycles.
#include <cstdio>

#include "tests/support/dc_master_steps.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr hal::Nanoseconds kCycle = hal::kNsPerMs;
constexpr std::uint64_t kMasterTime = 0x0123'4567'89AB'CDEFULL;

std::unique_ptr<Rig> synchronised_rig(const RobotSegmentOptions& options, bool model_delays) {
  auto rig = Rig::robot(options);
  prepare_distributed_clocks(*rig, kMasterTime, model_delays);
  return rig;
}

TEST(DcDriftCompensation, ConvergesToAFewNanosecondsWithTheTrueDelays) {
  RobotSegmentOptions options;
  options.seed = 7;
  auto rig = synchronised_rig(options, true);
  std::int64_t initial_error = 0;
  for (int cycle = 0; cycle < 20; ++cycle) distribute_reference_time(*rig, kCycle);
  initial_error = worst_sync_error(*rig, rig->now);
  int converged_at = -1;
  std::printf("dc: cycle worst-true-error-ns worst-0x092C-ns:");
  for (int cycle = 0; cycle < 8000; ++cycle) {
    distribute_reference_time(*rig, kCycle);
    if (converged_at < 0 && worst_sync_error(*rig, rig->now) <= 5 && worst_reported_difference(*rig) <= 5) converged_at = cycle;
    if (cycle == 0 || cycle == 50 || cycle == 100 || cycle == 200 || cycle == 400 || cycle == 700 || cycle == 1000 ||
        cycle == 1500 || cycle == 2000 || cycle == 4000) {
      std::printf(" %d:%lld/%lld", cycle, static_cast<long long>(worst_sync_error(*rig, rig->now)),
                  static_cast<long long>(worst_reported_difference(*rig)));
    }
  }
  std::printf("\n");
  std::printf("dc: initial error %lld ns, converged (<= 5 ns) after %d cycles, final error %lld ns, |0x092C| %lld ns\n",
              static_cast<long long>(initial_error), converged_at, static_cast<long long>(worst_sync_error(*rig, rig->now)),
              static_cast<long long>(worst_reported_difference(*rig)));
  EXPECT_GT(initial_error, 50);  // drift made the clocks diverge before the loop caught it
  EXPECT_GE(converged_at, 0);
  EXPECT_LT(converged_at, 6000);
  EXPECT_LE(worst_sync_error(*rig, rig->now), 5);
  EXPECT_LE(worst_reported_difference(*rig), 5);
}

TEST(DcDriftCompensation, HoldsAtTheExtremesOfCrystalDrift) {
  // Reference at -100 ppm, every other slave at +100 ppm: 200 ppm between them.
  RobotSegmentOptions options;
  auto rig = Rig::robot(options);
  std::array<SegmentSlave, kSlaveCount> slaves{};
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    slaves[p] = rig->segment.slave(p);
    slaves[p].esc.drift_ppm = p == 0 ? -100.0 : 100.0;
  }
  ASSERT_TRUE(rig->segment.build(Span<const SegmentSlave>(slaves), rig->now).ok());
  prepare_distributed_clocks(*rig, kMasterTime, true);
  for (int cycle = 0; cycle < 8000; ++cycle) distribute_reference_time(*rig, kCycle);
  EXPECT_LE(worst_sync_error(*rig, rig->now), 5);
  // The speed correction now cancels the 200 ppm (the speed counter difference shows it).
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    const double speed = rig->segment.esc(p).dc().clock().speed_correction();
    EXPECT_NEAR(speed, -200e-6, 2e-6) << kSlaves[p].name;
    EXPECT_NE(rig->segment.esc(p).register_u16(reg::kDcSpeedCounterDiff), 0) << kSlaves[p].name;
  }
}

TEST(DcDriftCompensation, MasterMeasuredDelaysLeaveOnlyTheirOwnErrorOfTensOfNanoseconds) {
  RobotSegmentOptions options;
  options.seed = 11;
  auto rig = synchronised_rig(options, false);
  for (int cycle = 0; cycle < 8000; ++cycle) distribute_reference_time(*rig, kCycle);
  const std::int64_t error = worst_sync_error(*rig, rig->now);
  std::printf("dc: with master-measured delays the worst slave is %lld ns from the reference\n", static_cast<long long>(error));
  EXPECT_LT(error, 60);
  EXPECT_LE(worst_reported_difference(*rig), 5);  // the slaves believe they are in sync
}

TEST(DcDriftCompensation, StaticCompensationBurstConvergesToo) {
  // Some masters send thousands of FRMW back to back before cyclic operation.
  RobotSegmentOptions options;
  options.seed = 3;
  auto rig = synchronised_rig(options, true);
  for (int i = 0; i < 15000; ++i) distribute_reference_time(*rig, 50 * hal::kNsPerUs);
  EXPECT_LE(worst_sync_error(*rig, rig->now), 5);
}

TEST(DcDriftCompensation, WritingSpeedCounterStartResetsTheLoop) {
  auto rig = synchronised_rig(RobotSegmentOptions{}, true);
  for (int cycle = 0; cycle < 100; ++cycle) distribute_reference_time(*rig, kCycle);
  EXPECT_EQ(rig->write(Command::BWR, 0, reg::kDcSpeedCounterStart, le16(0x1000)).wkc, kSlaveCount);
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    EXPECT_EQ(rig->segment.esc(p).register_u32(reg::kDcSystemTimeDifference), 0u);
    EXPECT_EQ(rig->segment.esc(p).register_u16(reg::kDcSpeedCounterDiff), 0u);
    EXPECT_EQ(rig->segment.esc(p).dc().clock().speed_correction(), 0.0);
  }
}

TEST(DcDriftCompensation, SystemTimeReadsAreTheLocalCopyAtTheFramesArrival) {
  auto rig = synchronised_rig(RobotSegmentOptions{}, true);
  const auto r64 = rig->read(Command::FPRD, 0x1005, reg::kDcSystemTime, 8);
  ASSERT_EQ(r64.wkc, 1);
  EXPECT_EQ(from_le(r64.data), rig->segment.esc(5).system_time_at(rig->segment.last_arrival(5)));
  const auto r32 = rig->read(Command::FPRD, 0x1005, reg::kDcSystemTime, 4);
  EXPECT_EQ(from_le(r32.data), rig->segment.esc(5).system_time_at(rig->segment.last_arrival(5)) & 0xFFFFFFFFULL);
  // After the offsets were written, every system time is near the master's time.
  EXPECT_LT(from_le(r64.data) - kMasterTime, 10 * hal::kNsPerMs);
}

}  // namespace
}  // namespace rescue::drivers::testing
