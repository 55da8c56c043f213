// The last stage of the RC tasks' references: a jump in what a task wants becomes a ramp within
// every joint's velocity and acceleration limits that ends on the wanted position without
// overshoot; a motion already within the limits passes unchanged, also when taken over at speed (a
// reset at the references sent and their speed: bumpless); joints out of service hold.
#include <gtest/gtest.h>

#include <cmath>

#include "core/kinematics/acceleration_limiter.hpp"
#include "core/kinematics/rescue_motion.hpp"

namespace rescue::kin {
namespace {

constexpr double kDt = 0.001;

TEST(AccelerationLimiter, AJumpBecomesARampWithinTheLimitsThatEndsOnTheTarget) {
  const JointVector start = ready_posture();
  JointVector wanted = start;
  for (const std::size_t j : kIkJoints) wanted(static_cast<Eigen::Index>(j)) += 0.3;  // every IK joint jumps
  AccelerationLimiter limiter(start, kDt);
  JointVector previous = start;
  JointVector speed = JointVector::Zero();
  double overshoot = 0.0;
  for (int k = 0; k < 3000; ++k) {
    const JointVector& q = limiter.step(wanted, 0);
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const auto row = static_cast<Eigen::Index>(j);
      const double v = (q(row) - previous(row)) / kDt;
      ASSERT_LE(std::fabs(v), kJoints[j].limits.velocity_max_rad_s * (1.0 + 1e-9)) << kJoints[j].name;
      ASSERT_LE(std::fabs(v - speed(row)), kJointAcceleration[j] * kDt * (1.0 + 1e-4)) << kJoints[j].name << " " << k;
      overshoot = std::max(overshoot, (q(row) - wanted(row)) * (wanted(row) > start(row) ? 1.0 : -1.0));
      speed(row) = v;
    }
    previous = q;
  }
  EXPECT_LT((limiter.position() - wanted).cwiseAbs().maxCoeff(), 1e-9) << "on the target";
  EXPECT_LT(overshoot, 1e-9);
  EXPECT_EQ(limiter.velocity().cwiseAbs().maxCoeff(), 0.0);
}

TEST(AccelerationLimiter, AMotionWithinTheLimitsPassesUnchanged) {
  const JointVector start = ready_posture();
  AccelerationLimiter limiter(start, kDt);
  for (int k = 0; k <= 2000; ++k) {
    // 0.2 rad of minimum jerk in 2 s on every IK joint: peak 0.19 rad/s, 0.58 rad/s^2.
    const double s = 10 * std::pow(k / 2000.0, 3) - 15 * std::pow(k / 2000.0, 4) + 6 * std::pow(k / 2000.0, 5);
    JointVector wanted = start;
    for (const std::size_t j : kIkJoints) wanted(static_cast<Eigen::Index>(j)) += 0.2 * s;
    const JointVector& q = limiter.step(wanted, 0);
    ASSERT_LT((q - wanted).cwiseAbs().maxCoeff(), 1e-12) << k;
    ASSERT_EQ(limiter.limited(), 0U) << k;
  }
}

TEST(AccelerationLimiter, AMotionTakenOverAtSpeedContinuesUnchangedOrBrakesWithinTheLimit) {
  // Every IK joint at half its speed limit when a new owner takes over (reset at position and speed).
  const JointVector start = ready_posture();
  JointVector speed = JointVector::Zero();
  for (const std::size_t j : kIkJoints) speed(static_cast<Eigen::Index>(j)) = 0.5 * kJoints[j].limits.velocity_max_rad_s;
  AccelerationLimiter limiter(start, kDt);
  limiter.reset(start, speed);
  EXPECT_EQ(limiter.velocity(), speed);
  // An owner continuing the motion: passes unchanged from the first period.
  for (int k = 1; k <= 50; ++k) {
    const JointVector wanted = start + speed * (k * kDt);
    ASSERT_LT((limiter.step(wanted, 0) - wanted).cwiseAbs().maxCoeff(), 1e-12) << k;
  }
  // An owner that wants the joints where they are taken over: each brakes at its acceleration limit
  // (never a stop dead), comes back without overshooting the wanted position, within its limits.
  const JointVector here = limiter.position();
  limiter.reset(here, speed);
  JointVector previous = here;
  JointVector v_before = speed;
  for (int k = 0; k < 2000; ++k) {
    const JointVector& q = limiter.step(here, 0);
    for (const std::size_t j : kIkJoints) {
      const auto row = static_cast<Eigen::Index>(j);
      const double v = (q(row) - previous(row)) / kDt;
      ASSERT_LE(std::fabs(v), kJoints[j].limits.velocity_max_rad_s * (1.0 + 1e-9)) << kJoints[j].name;
      ASSERT_LE(std::fabs(v - v_before(row)), kJointAcceleration[j] * kDt * (1.0 + 1e-6)) << kJoints[j].name << " " << k;
      v_before(row) = v;
    }
    previous = q;
  }
  EXPECT_LT((limiter.position() - here).cwiseAbs().maxCoeff(), 1e-9) << "back where it was taken over";
  // A joint with a jerk limit (the hands) restarts at rest: its moving average has no state that
  // continues a speed without a step back.
  JointVector hand_speed = JointVector::Zero();
  const auto hand = static_cast<Eigen::Index>(joint_index("l_hand"));
  hand_speed(hand) = 0.5;
  limiter.reset(here, hand_speed);
  EXPECT_EQ(limiter.velocity()(hand), 0.0);
}

TEST(AccelerationLimiter, JointsOutOfServiceHoldWhereTheyAre) {
  const JointVector start = ready_posture();
  AccelerationLimiter limiter(start, kDt);
  const JointMask lost = joint_bit(joint_index("l_elbow"));
  const JointVector wanted = start + JointVector::Constant(0.1);
  for (int k = 0; k < 100; ++k) (void)limiter.step(wanted, lost);
  const auto elbow = static_cast<Eigen::Index>(joint_index("l_elbow"));
  EXPECT_EQ(limiter.position()(elbow), start(elbow));
  EXPECT_GT(limiter.position()(static_cast<Eigen::Index>(joint_index("r_elbow"))), start(elbow));
}

}  // namespace
}  // namespace rescue::kin
