// Minimum-jerk profile: s from 0 to 1 with zero velocity and acceleration at both ends, symmetric,
// derivatives consistent with finite differences; pose interpolation hits both ends and follows the
// rotation geodesic. The rescue motion passes lowering, forwarding, backwarding continuously with
// the payload growing only while backwarding.
#include <gtest/gtest.h>

#include "core/kinematics/rescue_motion.hpp"

namespace rescue::kin {
namespace {

TEST(MinimumJerk, ProfileStartsAndEndsAtRestAndIsSymmetric) {
  EXPECT_DOUBLE_EQ(minimum_jerk(0.0).s, 0.0);
  EXPECT_DOUBLE_EQ(minimum_jerk(1.0).s, 1.0);
  EXPECT_DOUBLE_EQ(minimum_jerk(0.5).s, 0.5);
  EXPECT_DOUBLE_EQ(minimum_jerk(0.0).ds, 0.0);
  EXPECT_DOUBLE_EQ(minimum_jerk(1.0).ds, 0.0);
  EXPECT_DOUBLE_EQ(minimum_jerk(0.0).dds, 0.0);
  EXPECT_NEAR(minimum_jerk(1.0).dds, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(minimum_jerk(0.5).ds, 1.875);  // peak velocity of the profile
  EXPECT_DOUBLE_EQ(minimum_jerk(-1.0).s, 0.0);    // clamped
  EXPECT_DOUBLE_EQ(minimum_jerk(2.0).s, 1.0);
  for (double t = 0.01; t < 1.0; t += 0.01) {
    EXPECT_NEAR(minimum_jerk(t).s + minimum_jerk(1.0 - t).s, 1.0, 1e-12);
    const double h = 1e-6;
    EXPECT_NEAR((minimum_jerk(t + h).s - minimum_jerk(t - h).s) / (2 * h), minimum_jerk(t).ds, 1e-6);
    EXPECT_NEAR((minimum_jerk(t + h).ds - minimum_jerk(t - h).ds) / (2 * h), minimum_jerk(t).dds, 1e-5);
  }
}

TEST(MinimumJerk, PoseInterpolationHitsBothEndsAlongTheGeodesic) {
  const Pose a{rotation_exp(Vector3(0.1, -0.2, 0.3)), Vector3(0.5, 0.2, 0.6)};
  const Pose b{rotation_exp(Vector3(-0.4, 0.5, 0.2)), Vector3(0.7, 0.1, 0.3)};
  EXPECT_LT(pose_error(a, interpolate_pose(a, b, 0.0)).norm(), 1e-12);
  EXPECT_LT(pose_error(b, interpolate_pose(a, b, 1.0)).norm(), 1e-12);
  const Pose mid = interpolate_pose(a, b, 0.5);
  EXPECT_LT((mid.p - 0.5 * (a.p + b.p)).norm(), 1e-12);
  // Equal rotation angle from each end at s = 0.5.
  EXPECT_NEAR(rotation_log(a.R.transpose() * mid.R).norm(), rotation_log(mid.R.transpose() * b.R).norm(), 1e-12);
}

TEST(RescueMotion, PhasesFollowEachOtherContinuouslyWithThePayloadOnlyWhileBackwarding) {
  const RescueMotion motion(ready_posture());
  RescueSample previous = motion.sample(0.0);
  EXPECT_EQ(previous.phase, RescuePhase::lowering);
  double max_step = 0.0;
  RescuePhase last_phase = previous.phase;
  int phase_changes = 0;
  for (double t = 0.001; t < motion.duration_s() + 0.5; t += 0.001) {
    const RescueSample s = motion.sample(t);
    max_step = std::max({max_step, (s.left.p - previous.left.p).norm(), (s.right.p - previous.right.p).norm()});
    if (s.phase != last_phase) ++phase_changes;
    if (s.phase == RescuePhase::lowering || s.phase == RescuePhase::forwarding) {
      EXPECT_EQ(s.payload_kg, 0.0);
    }
    EXPECT_GE(s.payload_kg, previous.payload_kg);
    last_phase = s.phase;
    previous = s;
  }
  EXPECT_EQ(phase_changes, 3);  // lowering -> forwarding -> backwarding -> done
  EXPECT_EQ(previous.phase, RescuePhase::done);
  EXPECT_DOUBLE_EQ(previous.payload_kg, 70.0);
  EXPECT_LT(max_step, 2e-4) << "no jump: at most 0.2 mm per 1 ms period (peak 1.875 x mean speed)";
  EXPECT_STREQ(to_string(RescuePhase::backwarding), "backwarding");
}

}  // namespace
}  // namespace rescue::kin
