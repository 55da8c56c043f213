// The second RC task: joint-space teleoperation integrates operator velocities within velocity,
// acceleration and position limits, holds joints out of service, computes while not owning the motion, and
// continues from the owner's references when it takes ownership (no jump).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/kinematics/joint_space_teleop.hpp"
#include "core/kinematics/rc_period.hpp"

namespace rescue::kin {
namespace {

TEST(JointSpaceTeleop, IntegratesWithinVelocityAccelerationAndPositionLimits) {
  JointSpaceTeleop teleop(JointVector::Zero());
  JointVector command = JointVector::Constant(100.0);  // far above every velocity limit
  JointVector previous = teleop.references();
  JointVector speed = JointVector::Zero();
  for (int k = 0; k < 8000; ++k) {
    if (k == 5000) command = -command;  // and back, at full speed
    ASSERT_TRUE(teleop.step(command, 0).ok());
    const JointVector v = (teleop.references() - previous) / 0.001;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const auto row = static_cast<Eigen::Index>(j);
      const JointLimits& lim = kJoints[j].limits;
      ASSERT_LE(std::fabs(v(row)), lim.velocity_max_rad_s * (1.0 + 1e-9)) << kJoints[j].name;
      ASSERT_LE(std::fabs(v(row) - speed(row)), kJointAcceleration[j] * 0.001 * (1.0 + 1e-4)) << kJoints[j].name << " k " << k;
      if (!kJoints[j].continuous) {
        ASSERT_LE(teleop.references()(row), lim.position_max_rad) << kJoints[j].name;
        ASSERT_GE(teleop.references()(row), lim.position_min_rad) << kJoints[j].name;
      }
    }
    if (k == 4999) {
      for (std::size_t j = 0; j < kJointCount; ++j) {
        const JointLimits& lim = kJoints[j].limits;
        const double q = teleop.references()(static_cast<Eigen::Index>(j));
        // Accelerating to v_max costs v_max^2 / (2 a_max) of the distance (to within v_max dt in
        // periods of dt).
        const double free_run = lim.velocity_max_rad_s * 5.0 -
                                lim.velocity_max_rad_s * lim.velocity_max_rad_s / (2.0 * kJointAcceleration[j]);
        if (kJoints[j].continuous) {
          EXPECT_NEAR(q, free_run, lim.velocity_max_rad_s * 0.001) << kJoints[j].name;  // tracks integrate freely
        } else if (free_run > lim.position_max_rad + 0.1) {
          EXPECT_NEAR(q, lim.position_max_rad, 1e-6) << kJoints[j].name << " stopped at its limit";
        }
      }
    }
    previous = teleop.references();
    speed = v;
  }
}

TEST(JointSpaceTeleop, HoldsJointsOutOfServiceAndRefusesNonFiniteCommands) {
  JointSpaceTeleop teleop(JointVector::Zero());
  const JointMask lost = joint_bit(joint_index("r_elbow"));
  ASSERT_TRUE(teleop.step(JointVector::Constant(0.5), lost).ok());
  EXPECT_EQ(teleop.references()(static_cast<Eigen::Index>(joint_index("r_elbow"))), 0.0);
  EXPECT_GT(teleop.references()(static_cast<Eigen::Index>(joint_index("l_elbow"))), 0.0);
  JointVector bad = JointVector::Zero();
  bad(3) = std::numeric_limits<double>::quiet_NaN();
  const JointVector before = teleop.references();
  const Status s = teleop.step(bad, 0);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::invalid_argument);
  EXPECT_EQ(teleop.references(), before);
}

TEST(JointSpaceTeleop, ComputesAlongsideTheRescueTaskAndTakesOverWithoutAJump) {
  RcPeriod rc(ready_posture());
  JointVector nudge = JointVector::Zero();
  nudge(static_cast<Eigen::Index>(joint_index("neck_pan"))) = 0.5;
  for (int k = 0; k < 2000; ++k) ASSERT_TRUE(rc.run(k * 0.001, 0, nudge).ok());
  EXPECT_FALSE(rc.teleop().owns_motion());
  // 0.5 rad/s for 2 s, less the ramp up to it at the neck's acceleration limit (0.5^2 / (2 a), to
  // within 0.5 rad/s dt in periods of dt).
  const double ramp = 0.25 / (2.0 * kJointAcceleration[joint_index("neck_pan")]);
  EXPECT_NEAR(rc.teleop_references()(static_cast<Eigen::Index>(joint_index("neck_pan"))), 1.0 - ramp, 0.5e-3)
      << "teleop computed its own references while the rescue task owned the motion";
  // The operator hands the motion to teleoperation: it starts from what was being sent.
  const JointVector sent = rc.rescue_references();
  rc.teleop().take_ownership(sent);
  EXPECT_TRUE(rc.teleop().owns_motion());
  ASSERT_TRUE(rc.teleop().step(JointVector::Zero(), 0).ok());
  EXPECT_EQ(rc.teleop_references(), sent);
  rc.teleop().release_ownership();
  EXPECT_FALSE(rc.teleop().owns_motion());
}

}  // namespace
}  // namespace rescue::kin
