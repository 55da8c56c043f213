// The optional jerk limit (the URDF's <limit jerk>, kJointJerk): the acceleration limiter keeps the
// references of a joint that declares one within its jerk, acceleration and velocity limits, ends
// a jump on the target, and passes a motion within the limits unchanged; joints without one keep
// the acceleration-only ramps. The hand grippers declare one (docs/kinematics.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/kinematics/acceleration_limiter.hpp"
#include "core/kinematics/rescue_motion.hpp"

namespace rescue::kin {
namespace {

constexpr double kDt = 0.001;

struct Extremes {
  double speed{0.0};         // largest |v| / v_max
  double acceleration{0.0};  // largest |a| / a_max
  double jerk{0.0};          // largest |j|, rad/s^3
  double overshoot{0.0};     // furthest beyond the target, rad
  double error{0.0};         // |x - target| at the end, rad
  int periods_to_target{-1};
};

// Runs `periods` of the limiter towards `wanted` (changed to `second` at `switch_at`, if given) and
// measures joint j's references by their differences, as a drive would see them.
Extremes measure(AccelerationLimiter& limiter, std::size_t j, JointVector wanted, int periods,
                 int switch_at = -1, const JointVector* second = nullptr) {
  const auto row = static_cast<Eigen::Index>(j);
  Extremes out;
  double x = limiter.position()(row);
  const double start = x;
  double v = 0.0;
  double a = 0.0;
  for (int k = 0; k < periods; ++k) {
    if (k == switch_at && second != nullptr) wanted = *second;
    const double next = limiter.step(wanted, 0)(row);
    const double v_next = (next - x) / kDt;
    const double a_next = (v_next - v) / kDt;
    out.speed = std::max(out.speed, std::fabs(v_next) / kJoints[j].limits.velocity_max_rad_s);
    out.acceleration = std::max(out.acceleration, std::fabs(a_next) / kJointAcceleration[j]);
    out.jerk = std::max(out.jerk, std::fabs(a_next - a) / kDt);
    const double direction = wanted(row) >= start ? 1.0 : -1.0;
    if (k >= switch_at) out.overshoot = std::max(out.overshoot, (next - wanted(row)) * direction);
    if (out.periods_to_target < 0 && std::fabs(next - wanted(row)) < 1e-9 && std::fabs(v_next) < 1e-9) {
      out.periods_to_target = k + 1;
    }
    x = next;
    v = v_next;
    a = a_next;
  }
  out.error = std::fabs(x - wanted(row));
  return out;
}

TEST(JerkLimit, TheHandGrippersDeclareOneAndNoOtherDriveDoes) {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const bool hand = std::string(kJoints[j].name) == "l_hand" || std::string(kJoints[j].name) == "r_hand";
    EXPECT_EQ(kJointJerk[j] > 0.0, hand) << kJoints[j].name;
  }
  EXPECT_EQ(kJointJerk[joint_index("l_hand")], 50.0);
  EXPECT_EQ(kJointJerk[joint_index("r_hand")], 50.0);
}

TEST(JerkLimit, HandJumpsBecomeSCurvesWithinEveryLimitThatEndOnTheTarget) {
  for (const char* name : {"l_hand", "r_hand"}) {
    const std::size_t j = joint_index(name);
    const auto row = static_cast<Eigen::Index>(j);
    for (const double jump : {1e-4, 0.01, 0.1, 0.5, 1.1}) {
      const JointVector start = ready_posture();  // hands at 0.2 rad
      JointVector wanted = start;
      wanted(row) = std::clamp(start(row) + jump, kJoints[j].limits.position_min_rad, kJoints[j].limits.position_max_rad);
      AccelerationLimiter limiter(start, kDt);
      const Extremes e = measure(limiter, j, wanted, 4000);
      std::printf("%s jump %.4f rad: v %.3f, a %.3f of the limits, jerk %.2f rad/s^3, overshoot %.2e rad, "
                  "on target after %d ms\n",
                  name, wanted(row) - start(row), e.speed, e.acceleration, e.jerk, e.overshoot, e.periods_to_target);
      EXPECT_LE(e.speed, 1.0 + 1e-9) << name << " " << jump;
      EXPECT_LE(e.acceleration, 1.0 + 1e-6) << name << " " << jump;
      EXPECT_LE(e.jerk, kJointJerk[j] * (1.0 + 1e-6)) << name << " " << jump;
      EXPECT_LT(e.overshoot, 1e-6) << name << " " << jump;
      EXPECT_LT(e.error, 1e-9) << name << " " << jump;
      EXPECT_GT(e.periods_to_target, 0) << name << " " << jump;
    }
  }
}

TEST(JerkLimit, ATargetReversedWhileMovingStaysWithinTheLimits) {
  const std::size_t j = joint_index("l_hand");
  const auto row = static_cast<Eigen::Index>(j);
  const JointVector start = ready_posture();
  JointVector open = start;
  open(row) = 1.4;
  JointVector closed = start;
  closed(row) = 0.05;
  AccelerationLimiter limiter(start, kDt);
  const Extremes e = measure(limiter, j, open, 5000, 600, &closed);  // reversed at full speed
  std::printf("l_hand reversed at 0.6 s: v %.3f, a %.3f of the limits, jerk %.2f rad/s^3, overshoot %.2e rad\n", e.speed,
              e.acceleration, e.jerk, e.overshoot);
  EXPECT_LE(e.speed, 1.0 + 1e-9);
  EXPECT_LE(e.acceleration, 1.0 + 1e-6);
  EXPECT_LE(e.jerk, kJointJerk[j] * (1.0 + 1e-6));
  EXPECT_LT(e.overshoot, 1e-6);
  EXPECT_LT(e.error, 1e-9);
}

TEST(JerkLimit, AHandMotionWithinTheLimitsArrivesHalfAWindowLate) {
  const std::size_t j = joint_index("r_hand");
  const auto row = static_cast<Eigen::Index>(j);
  const std::size_t window = jerk_window(kJointAcceleration[j], kJointJerk[j], kDt);
  EXPECT_EQ(window, 200U);  // 2 * 5 rad/s^2 / (50 rad/s^3 * 1 ms)
  const JointVector start = ready_posture();
  AccelerationLimiter limiter(start, kDt);
  const auto wanted_at = [&start, row](int k) {
    // 0.5 rad of minimum jerk in 2 s: peak 0.47 rad/s, 1.44 rad/s^2, 7.5 rad/s^3 (limits 2, 5, 50).
    const double t = std::clamp(k / 2000.0, 0.0, 1.0);
    const double s = 10 * std::pow(t, 3) - 15 * std::pow(t, 4) + 6 * std::pow(t, 5);
    JointVector wanted = start;
    wanted(row) += 0.5 * s;
    return wanted;
  };
  // The moving average of a motion is that motion (N - 1) / 2 periods late, to second order.
  const double late = (static_cast<double>(window) - 1.0) / 2.0;
  double lag_error = 0.0;
  for (int k = 0; k <= 2400; ++k) {
    const double q = limiter.step(wanted_at(k), 0)(row);
    const double t = k - late;
    const double delayed = wanted_at(static_cast<int>(std::floor(t)))(row) * (1.0 - (t - std::floor(t))) +
                           wanted_at(static_cast<int>(std::floor(t)) + 1)(row) * (t - std::floor(t));
    lag_error = std::max(lag_error, std::fabs(q - delayed));
  }
  std::printf("r_hand minimum-jerk 0.5 rad in 2 s: %zu-period window, off the motion %.1f ms late by at most %.2e rad\n",
              window, late, lag_error);
  EXPECT_LT(lag_error, 2e-3);  // measured 1.2e-3 rad (the second-order term of the average)
  EXPECT_EQ(limiter.position()(row), wanted_at(2000)(row)) << "on the target, exactly";
}

TEST(JerkLimit, AJointWithoutOneKeepsItsAccelerationRampAndGetsOneWhenDeclared) {
  const std::size_t j = joint_index("l_elbow");
  const auto row = static_cast<Eigen::Index>(j);
  const JointVector start = ready_posture();
  JointVector wanted = start;
  wanted(row) += 0.3;
  AccelerationLimiter model(start, kDt);  // the model's table: the elbow has no jerk limit
  const Extremes without = measure(model, j, wanted, 3000);
  JointArray jerk = kJointJerk;
  jerk[j] = 20.0;
  AccelerationLimiter declared(start, kDt, jerk);
  const Extremes with = measure(declared, j, wanted, 3000);
  std::printf("l_elbow 0.3 rad: jerk %.0f rad/s^3 without a limit, %.2f with 20 rad/s^3; on target after %d / %d ms\n",
              without.jerk, with.jerk, without.periods_to_target, with.periods_to_target);
  EXPECT_GT(without.jerk, 1000.0);  // the acceleration steps to a_max in one period
  EXPECT_LE(with.jerk, 20.0 * (1.0 + 1e-6));
  EXPECT_LE(with.acceleration, 1.0 + 1e-6);
  EXPECT_LT(with.overshoot, 1e-6);
  EXPECT_LT(with.error, 1e-9);
  EXPECT_GT(with.periods_to_target, without.periods_to_target);
}

}  // namespace
}  // namespace rescue::kin
