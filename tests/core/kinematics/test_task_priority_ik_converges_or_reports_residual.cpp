// The task-priority IK reaches reachable pairs of palm poses, settles at the closest pose with a
// reported residual on unreachable ones (never an error, never outside the limits), stays bounded
// near singularities by damping more, and refuses non-finite input.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "core/kinematics/rescue_motion.hpp"
#include "core/kinematics/task_priority_ik.hpp"
#include "tests/core/kinematics/random_configurations.hpp"

namespace rescue::kin {
namespace {

IkTargets targets_at(const JointVector& q) {
  LinkPoses poses;
  forward_kinematics(q, poses);
  return IkTargets{poses[kLeftEe], poses[kRightEe], 0.0};
}

bool within_limits(const JointVector& q) {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointLimits& lim = kJoints[j].limits;
    const double v = q(static_cast<Eigen::Index>(j));
    if (!kJoints[j].continuous && (v < lim.position_min_rad || v > lim.position_max_rad)) return false;
  }
  return true;
}

TEST(TaskPriorityIk, ReachesReachableTargetsFromNearbyStarts) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.15);
  int reached = 0;
  constexpr int kTrials = 30;
  for (int n = 0; n < kTrials; ++n) {
    // A goal configuration around the ready posture, a start perturbed from it.
    JointVector goal = ready_posture();
    for (const std::size_t j : kIkJoints) goal(static_cast<Eigen::Index>(j)) += noise(rng);
    goal = goal.cwiseMax(JointVector::Constant(-2.5)).cwiseMin(JointVector::Constant(2.5));
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const JointLimits& lim = kJoints[j].limits;
      if (!kJoints[j].continuous) {
        goal(static_cast<Eigen::Index>(j)) =
            std::clamp(goal(static_cast<Eigen::Index>(j)), lim.position_min_rad + 0.05, lim.position_max_rad - 0.05);
      }
    }
    JointVector q = ready_posture();
    TaskPriorityIk ik;
    const Result<IkStepReport> r = ik.solve(q, targets_at(goal), 0, 20000, 1e-4, 1e-3);
    ASSERT_TRUE(r.ok());
    if (r.value().position_residual_m[0] <= 1e-4 && r.value().position_residual_m[1] <= 1e-4 &&
        r.value().rotation_residual_rad[0] <= 1e-3 && r.value().rotation_residual_rad[1] <= 1e-3) {
      ++reached;
    }
    EXPECT_TRUE(within_limits(q));
  }
  EXPECT_GE(reached, kTrials * 9 / 10) << "reached " << reached << " of " << kTrials;
}

TEST(TaskPriorityIk, UnreachableTargetSettlesAtTheClosestPoseWithItsResidual) {
  JointVector q = ready_posture();
  IkTargets targets = targets_at(q);
  targets.left.p += Vector3(2.0, 0.5, 0.0);  // two metres in front: beyond the arm's reach
  TaskPriorityIk ik;
  IkStepReport first;
  IkStepReport last;
  JointVector next;
  for (int k = 0; k < 6000; ++k) {
    const Result<IkStepReport> r = ik.step(q, targets, 0, next);
    ASSERT_TRUE(r.ok()) << "an unreachable target is not an error";
    last = r.value();
    if (k == 0) first = last;
    ASSERT_TRUE(within_limits(next));
    q = next;
  }
  EXPECT_LT(last.position_residual_m[0], first.position_residual_m[0] - 0.2) << "moved towards the target";
  // The waist turns to help the stretched arm; damping trades a little of the other palm's pose.
  EXPECT_LT(last.position_residual_m[1], 0.005) << "the other palm stays near its pose";
  // The palm stretched towards the target: the residual is the target's distance beyond the reach.
  LinkPoses poses;
  forward_kinematics(q, poses);
  const Vector3 shoulder = poses[link_index("l_shoulder_roll_link")].p;
  const double reach = (poses[kLeftEe].p - shoulder).norm();
  EXPECT_GT(last.position_residual_m[0], 1.0);
  EXPECT_NEAR(last.position_residual_m[0], (targets.left.p - poses[kLeftEe].p).norm(), 1e-6);  // settled
  EXPECT_GT(reach, 0.8) << "the arm reaches out";
  EXPECT_GT(last.damping, 1e-3) << "stretched arm: singular, damped";
  // Converged: another step changes nothing noticeable.
  const Result<IkStepReport> again = ik.step(q, targets, 0, next);
  ASSERT_TRUE(again.ok());
  EXPECT_LT((next - q).cwiseAbs().maxCoeff(), 1e-4);
}

// The docs' claims, measured (docs/kinematics.md, "Unreachable targets").
// `steps` IK steps from q (updated) towards fixed targets; the right palm's largest distance from
// `other` on the way into *drift; the last step's report.
IkStepReport run_steps(TaskPriorityIk& ik, JointVector& q, const IkTargets& targets, int steps, const Vector3& other,
                       double* drift) {
  JointVector next;
  IkStepReport last;
  for (int k = 0; k < steps; ++k) {
    const Result<IkStepReport> r = ik.step(q, targets, 0, next);
    EXPECT_TRUE(r.ok());
    if (!r.ok()) return last;
    last = r.value();
    q = next;
    LinkPoses poses;
    forward_kinematics(q, poses);
    *drift = std::max(*drift, (poses[kRightEe].p - other).norm());
  }
  return last;
}

// The turned palm needs the waist turned further than the other arm's reach allows: the targets
// conflict, the main task's Jacobian goes singular and the damped steps settle where the clamped
// errors are in the ratio of the palms' damping. The palm further from its target is damped more
// (IkSettings::max_palm_damping_share), so the other palm, on its target, holds (docs: 0.4 mm).
double turned_palm_drift(const IkSettings& settings, IkStepReport& last, JointVector& q) {
  q = ready_posture();
  IkTargets targets = targets_at(q);
  const Vector3 other = targets.right.p;
  targets.left.R = Eigen::AngleAxisd(M_PI, Vector3::UnitZ()).toRotationMatrix() * targets.left.R;
  TaskPriorityIk ik(settings);
  double drift = 0.0;
  last = run_steps(ik, q, targets, 6000, other, &drift);
  std::printf("target palm turned by pi (palm damping share up to %.0f): other palm drift %.4f m (at the end %.4f m), "
              "target residual %.4f m %.4f rad, waist %.3f rad\n",
              settings.max_palm_damping_share, drift, last.position_residual_m[1], last.position_residual_m[0],
              last.rotation_residual_rad[0], q(0));
  return drift;
}

TEST(TaskPriorityIk, TargetPalmTurnedByPiAboutZLeavesTheOtherPalmWithin5Mm) {
  IkStepReport last;
  JointVector q;
  const double drift = turned_palm_drift(IkSettings{}, last, q);
  EXPECT_LT(drift, 0.005);
  EXPECT_LT(last.position_residual_m[1], 0.005);
  EXPECT_LT(last.rotation_residual_rad[1], 0.005);
  // The turned palm gets as close as the held one lets it: its rotation, not all of its position.
  EXPECT_LT(last.rotation_residual_rad[0], 0.01);
  EXPECT_LT(last.position_residual_m[0], 0.2);  // measured 0.139 m
}

TEST(TaskPriorityIk, WithoutThePalmDampingShareTheOtherPalmDrifts) {
  IkSettings equal;
  equal.max_palm_damping_share = 1.0;  // both palms damped alike: the behaviour before the share
  IkStepReport last;
  JointVector q;
  const double drift = turned_palm_drift(equal, last, q);
  // Measured: 14.0 mm on the way, 6.0 mm at the end (35 mm before the shoulders moved out).
  EXPECT_GT(drift, 0.01) << "the conflict this test is about is gone; revisit the docs";
}

TEST(TaskPriorityIk, FarLeftTargetSettlesWithTheArmBentNotStretched) {
  JointVector q = ready_posture();
  IkTargets targets = targets_at(q);
  targets.left.p += Vector3(0.0, 2.0, 0.0);  // two metres to the left, orientation kept
  TaskPriorityIk ik;
  double drift = 0.0;
  const IkStepReport last = run_steps(ik, q, targets, 6000, targets.right.p, &drift);
  LinkPoses poses;
  forward_kinematics(q, poses);
  const double wrist = (poses[link_index("l_wrist_link")].p - poses[link_index("l_upper_arm_link")].p).norm();
  std::printf("far left: residual %.4f m, elbow %.3f rad, shoulder yaw to wrist %.4f m (0.65 stretched)\n",
              last.position_residual_m[0], q(static_cast<Eigen::Index>(joint_index("l_elbow"))), wrist);
  // Keeping the palm's orientation, the closest pose the damped steps settle at keeps the elbow bent.
  EXPECT_GT(last.position_residual_m[0], 1.0);
  EXPECT_LT(wrist, 0.6);
  JointVector next;
  ASSERT_TRUE(ik.step(q, targets, 0, next).ok());
  EXPECT_LT((next - q).cwiseAbs().maxCoeff(), 1e-4) << "settled";
}

TEST(TaskPriorityIk, StepsStayBoundedAtASingularity) {
  JointVector q = JointVector::Zero();  // arms straight down: elbow and wrist singular
  IkTargets targets = targets_at(q);
  targets.left.p += Vector3(0.0, 0.0, 0.05);  // along the stretched arm
  targets.right.p += Vector3(0.0, 0.0, 0.05);
  TaskPriorityIk ik;
  JointVector next;
  const Result<IkStepReport> r = ik.step(q, targets, 0, next);
  ASSERT_TRUE(r.ok());
  EXPECT_LT(r.value().sigma_min, ik.settings().singular_threshold);
  EXPECT_GT(r.value().damping, 0.5 * ik.settings().max_damping);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    EXPECT_LE(std::fabs(next(static_cast<Eigen::Index>(j)) - q(static_cast<Eigen::Index>(j))),
              kJoints[j].limits.velocity_max_rad_s * 0.001 + 1e-12);
  }
}

TEST(TaskPriorityIk, PositionLimitsLockTheJointAtItsLimit) {
  JointVector q = ready_posture();
  const auto elbow = static_cast<Eigen::Index>(joint_index("l_elbow"));
  q(elbow) = kJoints[static_cast<std::size_t>(elbow)].limits.position_max_rad - 1e-3;
  IkTargets targets = targets_at(q);
  targets.left.p += Vector3(-0.05, 0.0, 0.05);  // pull the palm in: needs more elbow
  TaskPriorityIk ik;
  for (int k = 0; k < 2000; ++k) {
    JointVector next;
    const Result<IkStepReport> r = ik.step(q, targets, 0, next);
    ASSERT_TRUE(r.ok());
    ASSERT_TRUE(within_limits(next));
    q = next;
  }
  EXPECT_LE(q(elbow), kJoints[static_cast<std::size_t>(elbow)].limits.position_max_rad);
}

TEST(TaskPriorityIk, RefusesNonFiniteInputAndLeavesReferencesAlone) {
  TaskPriorityIk ik;
  JointVector q = ready_posture();
  JointVector next = JointVector::Constant(7.0);
  IkTargets targets = targets_at(q);
  targets.right.p.x() = std::numeric_limits<double>::quiet_NaN();
  const Result<IkStepReport> r = ik.step(q, targets, 0, next);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::invalid_argument);
  EXPECT_EQ(next, JointVector::Constant(7.0));
  q(0) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(ik.step(q, targets_at(ready_posture()), 0, next).ok());
}

}  // namespace
}  // namespace rescue::kin
