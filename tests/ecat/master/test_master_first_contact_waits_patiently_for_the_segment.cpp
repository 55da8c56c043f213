// Issue 11 item 4: the master gave up after three BRDs 2 ms apart when the segment (a simulator
// that had been idle, a segment still powering up) did not answer at once. First contact now
// repeats the count BRD every frame_timeout until first_contact_timeout, and says clearly when
// nothing answered. Virtual time: the simulated segment loses frames on purpose.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

TEST(MasterFirstContact, WaitsForASegmentThatAnswersOnlyAfterSeveralFrames) {
  auto rig = std::make_unique<SimulatedRobotRig>();
  ASSERT_TRUE(rig->built.ok());
  rig->segment.drop_frames(40);  // 80 ms of silence at 2 ms per BRD: far beyond three attempts
  const Status up = rig->bus.bring_up(testing::fast_options());
  ASSERT_TRUE(up.ok()) << testing::describe_master_failure(rig->bus.master());
  EXPECT_EQ(rig->bus.master().report().first_contact_frames, 41U);
  EXPECT_EQ(rig->bus.master().report().slaves_counted, kSlaveCount);
}

TEST(MasterFirstContact, NothingAnsweringFailsAfterTheFirstContactTimeWithAClearMessage) {
  auto rig = std::make_unique<SimulatedRobotRig>();
  ASSERT_TRUE(rig->built.ok());
  rig->segment.drop_frames(1'000'000);
  MasterOptions options = testing::fast_options();
  options.first_contact_timeout = 300 * hal::kNsPerMs;
  const hal::Nanoseconds start = rig->clock.now();
  const Status up = rig->bus.bring_up(options);
  ASSERT_FALSE(up.ok());
  const BringUpReport& report = rig->bus.master().report();
  EXPECT_STREQ(report.failed_step, "count");
  EXPECT_EQ(up.error().code, Errc::timeout);
  EXPECT_NE(std::strstr(up.error().what, "no EtherCAT frame came back"), nullptr) << up.error().what;
  EXPECT_EQ(up.error().detail0, report.first_contact_frames);
  EXPECT_EQ(up.error().detail1, 300U) << "the time waited, in ms";
  EXPECT_EQ(report.first_contact_frames, 150U) << "one BRD per frame_timeout (2 ms) over 300 ms";
  EXPECT_GE(rig->clock.now() - start, options.first_contact_timeout);
}

}  // namespace
}  // namespace rescue::ecat
