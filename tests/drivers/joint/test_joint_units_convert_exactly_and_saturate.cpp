// The joint driver's unit conversions (drivers/joint/joint_units.hpp): every shared record is in SI
// units, so a reference aligned with an actual position must reach the drive as the very count the
// drive reported (enabling then moves nothing), and out-of-range values saturate instead of wrapping.
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "core/robot/robot.hpp"
#include "drivers/joint/joint_units.hpp"

namespace rescue::drivers {
namespace {

TEST(JointUnits, EveryCountSurvivesTheRoundTripThroughRadians) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::int32_t> any(std::numeric_limits<std::int32_t>::min(),
                                                  std::numeric_limits<std::int32_t>::max());
  for (int i = 0; i < 1000000; ++i) {
    const std::int32_t c = any(rng);
    ASSERT_EQ(rad_to_counts(counts_to_rad(c)), c) << c;
  }
  for (std::int32_t c = -70000; c <= 70000; ++c) ASSERT_EQ(rad_to_counts(counts_to_rad(c)), c) << c;
  for (const std::int32_t c : {std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max()}) {
    EXPECT_EQ(rad_to_counts(counts_to_rad(c)), c);
  }
}

TEST(JointUnits, OneRevolutionIsTwoToTheTwentyCounts) {
  EXPECT_EQ(rad_to_counts(2.0 * 3.141592653589793), 1048576);
  EXPECT_NEAR(counts_to_rad(rad_to_counts(1.25)), 1.25, 1e-5);
}

TEST(JointUnits, OutOfRangeSaturatesAndNanGoesToTheBottom) {
  EXPECT_EQ(rad_to_counts(1e9), std::numeric_limits<std::int32_t>::max());
  EXPECT_EQ(rad_to_counts(-1e9), std::numeric_limits<std::int32_t>::min());
  EXPECT_EQ(rad_to_counts(std::nan("")), std::numeric_limits<std::int32_t>::min());
}

TEST(JointUnits, TorqueIsPerMilleOfTheJointsRatedTorque) {
  const JointInfo& elbow = kJoints[joint_index_by_name("l_elbow")];
  EXPECT_DOUBLE_EQ(per_mille_to_nm(1000, elbow), elbow.rated_torque_nm);
  EXPECT_DOUBLE_EQ(per_mille_to_nm(-500, elbow), -0.5 * elbow.rated_torque_nm);
  EXPECT_EQ(nm_to_per_mille(elbow.rated_torque_nm, elbow), 1000);
  EXPECT_EQ(nm_to_per_mille(1e9, elbow), std::numeric_limits<std::int16_t>::max());
  EXPECT_EQ(nm_to_per_mille(-1e9, elbow), std::numeric_limits<std::int16_t>::min());
  for (std::int16_t v = -2000; v <= 2000; ++v) ASSERT_EQ(nm_to_per_mille(per_mille_to_nm(v, elbow), elbow), v);
}

}  // namespace
}  // namespace rescue::drivers
