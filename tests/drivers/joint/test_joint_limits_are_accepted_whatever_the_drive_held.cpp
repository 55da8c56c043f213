// Issue 35, item 14: after another tool set both software position limits (0x607D:01 and :02) to
// INT32_MIN, the master wrote :01 (the joint's min, above the held max) first and the drive aborted
// with 0x06090036 (max below min): the first bring-up failed. The limits are now written :01 =
// INT32_MIN, :02, :01, which keeps min <= max at every step whatever the drive held (the simulated
// drive refuses min > max with that abort code, as a real one does:
// test_joint_drive_objects_accept_only_the_fixed_mapping). Every joint's drive ends with the joint's
// own limits, from any foreign pair.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "drivers/joint/joint_units.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::drivers {
namespace {

using testing::SimulatedRobotRig;

constexpr std::int32_t kLowest = std::numeric_limits<std::int32_t>::min();
constexpr std::int32_t kHighest = std::numeric_limits<std::int32_t>::max();

void hold_foreign_limits(SimulatedRobotRig& rig, std::int32_t min, std::int32_t max) {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (kJoints[j].continuous) continue;
    ObjectDictionary& od = rig.drive(j).objects().od();
    od.set(0x607D, 1, static_cast<std::uint32_t>(min));
    od.set(0x607D, 2, static_cast<std::uint32_t>(max));
  }
}

void expect_joint_limits(SimulatedRobotRig& rig) {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (kJoints[j].continuous) continue;
    const ObjectDictionary& od = rig.drive(j).objects().od();
    EXPECT_EQ(od.get_i32(0x607D, 1), rad_to_counts(kJoints[j].limits.position_min_rad)) << kJoints[j].name;
    EXPECT_EQ(od.get_i32(0x607D, 2), rad_to_counts(kJoints[j].limits.position_max_rad)) << kJoints[j].name;
  }
}

TEST(JointLimitsWrittenAtBringUp, AreAcceptedWhateverForeignLimitsTheDrivesHeld) {
  const std::vector<std::pair<std::int32_t, std::int32_t>> foreign = {
      {kLowest, kLowest}, {kHighest, kHighest}, {kLowest, kHighest}, {0, 0}, {-5, 5}, {1 << 30, 1 << 30}, {-(1 << 30), -(1 << 30)}};
  for (const auto& [min, max] : foreign) {
    auto rig = std::make_unique<SimulatedRobotRig>();
    hold_foreign_limits(*rig, min, max);
    const Status up = rig->bus.bring_up(testing::fast_options());
    ASSERT_TRUE(up.ok()) << "foreign limits " << min << ".." << max << ": " << testing::describe_master_failure(rig->bus.master());
    expect_joint_limits(*rig);
  }
}

}  // namespace
}  // namespace rescue::drivers
