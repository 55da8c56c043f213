// The property the RC tasks and the Motion intake rely on: whatever the wanted positions do (jumps,
// short blips, reversals faster than the limits, targets beyond the position limits, a joint told to
// brake, a joint out of service and back), every reference the limiter gives keeps every joint's
// position, speed and acceleration limits, and its jerk limit where it declares one, every period;
// and a target inside the limits that is held is never passed when it could be reached at rest.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/kinematics/acceleration_limiter.hpp"
#include "core/kinematics/rescue_motion.hpp"

namespace rescue::kin {
namespace {

constexpr double kDt = 0.001;

// The distance a joint moving at `speed` covers while it brakes at a_max, period by period as the
// limiter brakes (this period's move included).
double stopping_distance(double speed, double a_max) {
  double distance = 0.0;
  for (double v = std::fabs(speed); v > 0.0; v -= a_max * kDt) distance += v * kDt;
  return distance;
}

// Per joint, a random wanted motion: segments of a held target (inside or beyond the limits), a blip
// (a few periods away and back), a fast sine, or a ramp faster than the velocity limit.
struct WantedJoint {
  enum class Kind { hold, blip, sine, ramp } kind{Kind::hold};
  int left{0};          // periods until the next segment
  double base{0.0};
  double target{0.0};
  double amplitude{0.0};
  double omega{0.0};
  double rate{0.0};
  int age{0};
  int blip_periods{0};
};

double span(std::size_t j) {
  const JointLimits& lim = kJoints[j].limits;
  return kJoints[j].continuous ? 6.0 : lim.position_max_rad - lim.position_min_rad;
}
double centre(std::size_t j) {
  const JointLimits& lim = kJoints[j].limits;
  return kJoints[j].continuous ? 0.0 : 0.5 * (lim.position_min_rad + lim.position_max_rad);
}

void next_segment(WantedJoint& w, std::size_t j, double now_position, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> kind(0, 3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> length(1, 1500);
  w.kind = static_cast<WantedJoint::Kind>(kind(rng));
  w.left = length(rng);
  w.age = 0;
  w.base = now_position;
  // Targets up to 30 % of the range beyond either limit.
  w.target = centre(j) + 0.65 * span(j) * unit(rng);
  w.amplitude = 0.5 * span(j) * unit(rng);
  w.omega = 40.0 * std::fabs(unit(rng));
  w.rate = 3.0 * kJoints[j].limits.velocity_max_rad_s * unit(rng);
  w.blip_periods = 1 + static_cast<int>(5.0 * std::fabs(unit(rng)));
}

double wanted_of(const WantedJoint& w) {
  switch (w.kind) {
    case WantedJoint::Kind::hold: return w.target;
    case WantedJoint::Kind::blip: return w.age < w.blip_periods ? w.target : w.base;
    case WantedJoint::Kind::sine: return w.base + w.amplitude * std::sin(w.omega * w.age * kDt);
    case WantedJoint::Kind::ramp: return w.base + w.rate * w.age * kDt;
  }
  return w.base;
}

TEST(AccelerationLimiterProperty, AMillionRandomPeriodsKeepPositionSpeedAccelerationAndJerkOnEveryJoint) {
  std::mt19937_64 rng(20261129);
  const JointVector start = ready_posture();
  AccelerationLimiter limiter(start, kDt);
  std::array<WantedJoint, kJointCount> wanted_joints{};
  for (std::size_t j = 0; j < kJointCount; ++j) next_segment(wanted_joints[j], j, start(static_cast<Eigen::Index>(j)), rng);
  JointVector previous = start;
  JointVector speed = JointVector::Zero();
  JointVector acceleration = JointVector::Zero();
  JointMask was_out = 0;
  JointMask out_of_service = 0;
  JointMask braking = 0;
  std::uniform_int_distribution<int> rare(0, 20000);  // a joint starts braking, or goes out of service
  std::uniform_int_distribution<int> back(0, 300);    // and is driven again, or back in service
  std::uint64_t checks = 0;
  std::uint64_t violations = 0;
  double worst_jerk_ratio = 0.0;
  double worst_acceleration_ratio = 0.0;
  constexpr int kPeriods = 1'000'000;
  JointVector wanted = start;
  for (int k = 0; k < kPeriods; ++k) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      WantedJoint& w = wanted_joints[j];
      if (--w.left <= 0) next_segment(w, j, previous(static_cast<Eigen::Index>(j)), rng);
      wanted(static_cast<Eigen::Index>(j)) = wanted_of(w);
      ++w.age;
      // Now and then a joint is told to brake, or goes out of service, for a while.
      if (((braking & joint_bit(j)) != 0 ? back(rng) : rare(rng)) == 0) braking ^= joint_bit(j);
      if (((out_of_service & joint_bit(j)) != 0 ? back(rng) : rare(rng)) == 0) out_of_service ^= joint_bit(j);
    }
    const JointVector& q = limiter.step(wanted, out_of_service, braking);
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const auto row = static_cast<Eigen::Index>(j);
      const JointLimits& lim = kJoints[j].limits;
      const double v = (q(row) - previous(row)) / kDt;
      const double a = (v - speed(row)) / kDt;
      const double jerk = (a - acceleration(row)) / kDt;
      const bool judged = ((out_of_service | was_out) & joint_bit(j)) == 0;
      if (judged) {
        ++checks;
        bool bad = std::fabs(v) > lim.velocity_max_rad_s * (1.0 + 1e-9);
        bad = bad || std::fabs(a) > kJointAcceleration[j] * (1.0 + 1e-6) + 1e-6;
        if (!kJoints[j].continuous) bad = bad || q(row) < lim.position_min_rad || q(row) > lim.position_max_rad;
        worst_acceleration_ratio = std::max(worst_acceleration_ratio, std::fabs(a) / kJointAcceleration[j]);
        if (kJointJerk[j] > 0.0) {
          bad = bad || std::fabs(jerk) > kJointJerk[j] * (1.0 + 1e-6) + 1e-3;
          worst_jerk_ratio = std::max(worst_jerk_ratio, std::fabs(jerk) / kJointJerk[j]);
        }
        if (bad) {
          ++violations;
          ADD_FAILURE() << kJoints[j].name << " period " << k << ": x " << q(row) << " v " << v << " a " << a
                        << " jerk " << jerk;
          if (violations > 10) return;
        }
      }
      speed(row) = v;
      acceleration(row) = a;
    }
    was_out = out_of_service;
    previous = q;
  }
  EXPECT_EQ(violations, 0U);
  // Out of service is rare: nearly every joint-period is judged.
  EXPECT_GT(static_cast<double>(checks), 0.95 * kPeriods * kJointCount);
  // The limits are reached, not just respected from afar.
  EXPECT_GT(worst_acceleration_ratio, 0.99);
  EXPECT_GT(worst_jerk_ratio, 0.5);
  std::printf("limiter property: %llu joint-periods judged, 0 violations, worst |a|/a_max %.6f, worst |jerk|/j_max %.6f\n",
              static_cast<unsigned long long>(checks), worst_acceleration_ratio, worst_jerk_ratio);
}

// A joint heading for its position limit at speed, its wanted position blipping back for a period and
// on again (the r_wrist_pitch case: it arrived with speed and stopped in one period, 33.7x its
// acceleration limit): it brakes in time and arrives at rest, within its acceleration limit.
TEST(AccelerationLimiterProperty, ABlipNearAPositionLimitArrivesAtRestWithinTheAccelerationLimit) {
  const std::size_t j = joint_index("r_wrist_pitch");
  const auto row = static_cast<Eigen::Index>(j);
  const JointLimits& lim = kJoints[j].limits;
  JointVector start = ready_posture();
  start(row) = lim.position_max_rad - 0.3;
  AccelerationLimiter limiter(start, kDt);
  JointVector wanted = start;
  double previous = start(row);
  double speed = 0.0;
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    // Towards (and beyond) the limit at the velocity limit, with a one-period blip back at k = 150.
    wanted(row) = std::min(start(row) + lim.velocity_max_rad_s * k * kDt, lim.position_max_rad + 0.1);
    if (k == 150) wanted(row) = start(row);
    const double q = limiter.step(wanted, 0)(row);
    const double v = (q - previous) / kDt;
    worst = std::max(worst, std::fabs(v - speed) / kDt);
    ASSERT_LE(q, lim.position_max_rad);
    previous = q;
    speed = v;
  }
  EXPECT_LE(worst, kJointAcceleration[j] * (1.0 + 1e-6));
  EXPECT_EQ(previous, lim.position_max_rad) << "at the limit";
  EXPECT_EQ(speed, 0.0) << "at rest";
}

// Held targets inside the limits, from rest and from motion towards them from far enough away to
// stop at the acceleration limit: the references end on the target and never pass it, on every joint
// (a joint with a jerk limit from rest: its filtered ramp needs more room to stop than a_max gives).
TEST(AccelerationLimiterProperty, AHeldTargetInsideTheLimitsIsNeverPassed) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (kJoints[j].continuous) continue;
    const auto row = static_cast<Eigen::Index>(j);
    const JointLimits& lim = kJoints[j].limits;
    for (int trial = 0; trial < 20; ++trial) {
      JointVector start = ready_posture();
      start(row) = centre(j) + 0.45 * span(j) * unit(rng);
      AccelerationLimiter limiter(start, kDt);
      JointVector wanted = start;
      // First a motion at a random speed for a random time, then a target held inside the limits.
      const double rate = lim.velocity_max_rad_s * unit(rng);
      const int moving = kJointJerk[j] > 0.0 ? 0 : static_cast<int>(400 * std::fabs(unit(rng)));
      for (int k = 0; k < moving; ++k) {
        wanted(row) = std::clamp(start(row) + rate * k * kDt, lim.position_min_rad + 0.01, lim.position_max_rad - 0.01);
        (void)limiter.step(wanted, 0);
      }
      const double x0 = limiter.position()(row);
      const double v0 = limiter.velocity()(row);
      const double target = std::clamp(centre(j) + 0.45 * span(j) * unit(rng), lim.position_min_rad, lim.position_max_rad);
      const double direction = target >= x0 ? 1.0 : -1.0;
      // Only a target the joint can still reach at rest is a promise.
      if (v0 * direction < 0.0 || stopping_distance(v0, kJointAcceleration[j]) + 1e-9 > std::fabs(target - x0)) continue;
      wanted(row) = target;
      for (int k = 0; k < 10000; ++k) {
        const double q = limiter.step(wanted, 0)(row);
        // Never past it (by more than the rounding of the sums that close the gap: a nanoradian).
        ASSERT_LE((q - target) * direction, 1e-9) << kJoints[j].name << " trial " << trial << " period " << k;
        if (q == target && limiter.velocity()(row) == 0.0) break;
      }
      EXPECT_NEAR(limiter.position()(row), target, 1e-9) << kJoints[j].name;
    }
  }
}

// A joint told to brake comes to rest within its acceleration limit and holds; driven again, it
// starts from where it stopped (no jump).
TEST(AccelerationLimiterProperty, ABrakingJointComesToRestAndResumesWithoutAJump) {
  const std::size_t j = joint_index("l_shoulder_pitch");
  const auto row = static_cast<Eigen::Index>(j);
  const JointVector start = ready_posture();
  AccelerationLimiter limiter(start, kDt);
  JointVector wanted = start;
  // Up to 0.5 rad/s within the acceleration limit (the limiter passes it unchanged), then cruising.
  double speed = 0.0;
  for (int k = 0; k < 500; ++k) {
    speed = std::min(0.5, speed + 0.5 * kJointAcceleration[j] * kDt);
    wanted(row) += speed * kDt;
    (void)limiter.step(wanted, 0);
  }
  ASSERT_NEAR(limiter.velocity()(row), 0.5, 1e-6);
  double previous_speed = limiter.velocity()(row);
  int periods_to_rest = 0;
  for (int k = 0; k < 1000; ++k) {
    (void)limiter.step(wanted, 0, joint_bit(j));
    const double v = limiter.velocity()(row);
    ASSERT_LE(std::fabs(v - previous_speed), kJointAcceleration[j] * kDt * (1.0 + 1e-9));
    if (v != 0.0) periods_to_rest = k + 1;
    previous_speed = v;
  }
  EXPECT_EQ(limiter.velocity()(row), 0.0);
  EXPECT_LE(periods_to_rest, static_cast<int>(std::ceil(0.5 / (kJointAcceleration[j] * kDt))));
  const double rest = limiter.position()(row);
  wanted(row) = rest;
  (void)limiter.step(wanted, 0);
  EXPECT_EQ(limiter.position()(row), rest) << "driven again from where it stopped";
}

}  // namespace
}  // namespace rescue::kin
