// Static drift compensation (docs/master.md, Distributed clocks step 4) ends once every DC slave's
// system time difference (0x092C) is within its target in two checks in a row, instead of always
// sending ETG.1020's 15000 frames: on the simulated robot with +-100 ppm crystals it stops after a
// tenth of them, and the clocks are then as close to the reference as after all 15000 (the true
// offsets in the model, and the SYNC0 latches of the first cycles). Its frames are streamed, two on
// their way at a time: the compensation takes a third of the time of frames sent one by one, and
// leaves the clocks as close.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

struct DcOutcome {
  std::uint32_t static_frames{0};
  hal::Nanoseconds took{0};             // the "DC drift" step
  std::int64_t true_max_offset_ns{0};  // worst |system time - reference's| in the model, after bring-up
};

DcOutcome bring_up_with(unsigned frames, std::uint32_t target_ns, unsigned in_flight = MasterOptions{}.drift_compensation_in_flight) {
  drivers::RobotSegmentOptions segment;
  segment.seed = 3;
  segment.max_drift_ppm = 100.0;
  auto rig = std::make_unique<SimulatedRobotRig>(true, segment);
  EXPECT_TRUE(rig->built.ok());
  MasterOptions options;
  options.drift_compensation_frames = frames;
  options.drift_compensation_target_ns = target_ns;
  options.drift_compensation_in_flight = in_flight;
  EXPECT_TRUE(rig->bus.bring_up(options).ok()) << testing::describe_master_failure(rig->bus.master());
  DcOutcome out;
  const BringUpReport& report = rig->bus.master().report();
  out.static_frames = report.dc_static_frames;
  for (std::size_t i = 0; i + 1 < report.step_count; ++i) {
    if (std::string(report.steps[i].step) == "DC drift") out.took = report.steps[i + 1].at - report.steps[i].at;
  }
  const hal::Nanoseconds now = rig->clock.now();
  const std::uint64_t reference = rig->segment.esc(0).system_time_at(now);
  for (std::size_t p = 1; p < kSlaveCount; ++p) {
    const auto offset = static_cast<std::int64_t>(rig->segment.esc(p).system_time_at(now) - reference);
    out.true_max_offset_ns = std::max(out.true_max_offset_ns, std::abs(offset));
  }
  return out;
}

TEST(StaticDriftCompensation, EndsOnceConvergedWithTheClocksAsCloseAsAfterAllFrames) {
  const MasterOptions defaults;
  const DcOutcome full = bring_up_with(defaults.drift_compensation_frames, 0);
  const DcOutcome adaptive = bring_up_with(defaults.drift_compensation_frames, defaults.drift_compensation_target_ns);
  EXPECT_EQ(full.static_frames, defaults.drift_compensation_frames);
  EXPECT_LE(adaptive.static_frames, defaults.drift_compensation_frames / 5) << "it did not end early";
  EXPECT_GE(adaptive.static_frames, 2 * defaults.drift_compensation_check_every) << "two checks are needed";
  // As close as the full compensation leaves them, within the model's tens of nanoseconds.
  EXPECT_LE(adaptive.true_max_offset_ns, full.true_max_offset_ns + 10)
      << "full " << full.true_max_offset_ns << " ns after " << full.static_frames << " frames, adaptive "
      << adaptive.true_max_offset_ns << " ns after " << adaptive.static_frames;
}

TEST(StaticDriftCompensation, StreamedTakesAThirdOfTheTimeWithTheClocksAsClose) {
  const MasterOptions defaults;
  ASSERT_EQ(defaults.drift_compensation_in_flight, 2U);
  const DcOutcome one_by_one = bring_up_with(defaults.drift_compensation_frames, defaults.drift_compensation_target_ns, 1);
  const DcOutcome streamed = bring_up_with(defaults.drift_compensation_frames, defaults.drift_compensation_target_ns);
  ASSERT_GT(one_by_one.took, 0);
  ASSERT_GT(streamed.took, 0);
  EXPECT_LE(streamed.took, one_by_one.took / 2) << one_by_one.took << " ns one by one, " << streamed.took << " ns streamed";
  EXPECT_LE(streamed.true_max_offset_ns, one_by_one.true_max_offset_ns + 5)
      << "one by one " << one_by_one.true_max_offset_ns << " ns, streamed " << streamed.true_max_offset_ns << " ns";
}

TEST(StaticDriftCompensation, TargetZeroSendsEveryFrame) {
  EXPECT_EQ(bring_up_with(700, 0).static_frames, 700U);
}

}  // namespace
}  // namespace rescue::ecat
