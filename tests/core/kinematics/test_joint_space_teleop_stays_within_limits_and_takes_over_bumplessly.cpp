// The second RC task: joint-space teleoperation integrates operator velocities within velocity
// and position limits, holds joints out of service, computes while not owning the motion, and
// continues from the owner's references when it takes ownership (no jump).
#include <gtest/gtest.h>

#include <limits>

#include "core/kinematics/joint_space_teleop.hpp"
#include "core/kinematics/rc_period.hpp"

namespace rescue::kin {
namespace {

TEST(JointSpaceTeleop, IntegratesWithinVelocityAndPositionLimits) {
  JointSpaceTeleop teleop(JointVector::Zero());
  const JointVector command = JointVector::Constant(100.0);  // far above every velocity limit
  for (int k = 0; k < 5000; ++k) ASSERT_TRUE(teleop.step(command, 0).ok());
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointLimits& lim = kJoints[j].limits;
    const double q = teleop.references()(static_cast<Eigen::Index>(j));
    if (kJoints[j].continuous) {
      EXPECT_NEAR(q, lim.velocity_max_rad_s * 5.0, 1e-9) << kJoints[j].name;  // tracks integrate freely
    } else {
      EXPECT_DOUBLE_EQ(q, std::min(lim.position_max_rad, lim.velocity_max_rad_s * 5.0)) << kJoints[j].name;
    }
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
  EXPECT_NEAR(rc.teleop_references()(static_cast<Eigen::Index>(joint_index("neck_pan"))), 1.0, 1e-9)
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
