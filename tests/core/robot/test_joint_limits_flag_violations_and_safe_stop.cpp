// Limit monitoring: each limit of the robot's table, the reason and values recorded, and the EtherCAT
// handler's own safe-stop decision over all 21 joints.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/robot/joint_limits.hpp"

namespace rescue {
namespace {

const std::size_t kElbow = joint_index_by_name("l_elbow");    // position 0.0 .. 2.5, 2 rad/s, 80 Nm
const std::size_t kTrack = joint_index_by_name("l_track");    // continuous, 12 rad/s, 250 Nm

JointSample inside(std::size_t joint) {
  JointSample s{};
  s.reachable = true;
  const JointLimits& lim = kJoints[joint].limits;
  s.position_rad = s.position_ref_rad = 0.5 * (lim.position_min_rad + lim.position_max_rad);
  return s;
}

RobotSample all_inside() {
  RobotSample robot{};
  for (std::size_t j = 0; j < kJointCount; ++j) robot[j] = inside(j);
  return robot;
}

TEST(JointLimits, ValuesInsideEveryLimitPass) {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    EXPECT_FALSE(check_actual_limits(inside(j), kJoints[j]).active()) << kJoints[j].name;
    EXPECT_FALSE(check_reference_limits(inside(j), kJoints[j]).active()) << kJoints[j].name;
  }
}

TEST(JointLimits, LimitsThemselvesAreInside) {
  JointSample s = inside(kElbow);
  s.position_rad = 2.5;
  s.velocity_rad_s = -2.0;
  s.torque_nm = 80.0;
  EXPECT_FALSE(check_actual_limits(s, kJoints[kElbow]).active());
}

TEST(JointLimits, OutOfLimitPositionReferenceIsReportedWithValueAndLimit) {
  JointSample s = inside(kElbow);
  s.position_ref_rad = 2.6;
  const JointFault f = check_reference_limits(s, kJoints[kElbow]);
  EXPECT_EQ(f.reason, FaultReason::position_reference_limit);
  EXPECT_DOUBLE_EQ(f.value, 2.6);
  EXPECT_DOUBLE_EQ(f.limit, 2.5);
  s.position_ref_rad = -0.1;
  EXPECT_DOUBLE_EQ(check_reference_limits(s, kJoints[kElbow]).limit, 0.0);
}

TEST(JointLimits, ExceededVelocityAndTorqueInEitherDirection) {
  JointSample s = inside(kElbow);
  s.velocity_rad_s = -2.01;
  JointFault f = check_actual_limits(s, kJoints[kElbow]);
  EXPECT_EQ(f.reason, FaultReason::velocity_limit);
  EXPECT_DOUBLE_EQ(f.value, -2.01);
  EXPECT_DOUBLE_EQ(f.limit, 2.0);
  s = inside(kElbow);
  s.torque_nm = 80.5;
  EXPECT_EQ(check_actual_limits(s, kJoints[kElbow]).reason, FaultReason::torque_limit);
  s = inside(kElbow);
  s.velocity_ref_rad_s = 3.0;
  EXPECT_EQ(check_reference_limits(s, kJoints[kElbow]).reason, FaultReason::velocity_reference_limit);
  s = inside(kElbow);
  s.torque_ref_nm = -100.0;
  EXPECT_EQ(check_reference_limits(s, kJoints[kElbow]).reason, FaultReason::torque_reference_limit);
  s = inside(kElbow);
  s.position_rad = 3.0;
  EXPECT_EQ(check_actual_limits(s, kJoints[kElbow]).reason, FaultReason::position_limit);
}

TEST(JointLimits, ContinuousJointsHaveNoPositionLimitButKeepTheirVelocityLimit) {
  JointSample s = inside(kTrack);
  s.position_rad = s.position_ref_rad = 1234.5;
  EXPECT_FALSE(check_actual_limits(s, kJoints[kTrack]).active());
  EXPECT_FALSE(check_reference_limits(s, kJoints[kTrack]).active());
  s.velocity_ref_rad_s = 12.5;
  EXPECT_EQ(check_reference_limits(s, kJoints[kTrack]).reason, FaultReason::velocity_reference_limit);
}

TEST(JointLimits, NotFiniteValuesNeverPass) {
  for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    JointSample s = inside(kElbow);
    s.velocity_rad_s = bad;
    EXPECT_EQ(check_actual_limits(s, kJoints[kElbow]).reason, FaultReason::not_finite);
    s = inside(kTrack);
    s.position_ref_rad = bad;  // even where position is not limited
    EXPECT_EQ(check_reference_limits(s, kJoints[kTrack]).reason, FaultReason::not_finite);
  }
}

TEST(JointLimits, DriveFaultCarriesTheErrorCode) {
  JointSample s = inside(kElbow);
  EXPECT_FALSE(check_drive_fault(s).active());
  s.drive_fault = true;
  s.drive_error_code = 0x7500;
  const JointFault f = check_drive_fault(s);
  EXPECT_EQ(f.reason, FaultReason::drive_fault);
  EXPECT_DOUBLE_EQ(f.value, 0x7500);
  EXPECT_STREQ(to_string(f.reason), "drive fault");
}

TEST(SafeStop, NothingToDoWhenEveryMonitoredJointIsInside) {
  const SafeStopDecision d = decide_safe_stop(all_inside(), kAllJoints);
  EXPECT_FALSE(d.stop);
  EXPECT_EQ(d.violating, 0u);
  EXPECT_EQ(d.first_joint, kNoJoint);
}

TEST(SafeStop, AnyViolationStopsTheRobotAndNamesEveryViolatingJoint) {
  RobotSample robot = all_inside();
  robot[kElbow].velocity_rad_s = 5.0;
  robot[kTrack].torque_ref_nm = 300.0;
  const SafeStopDecision d = decide_safe_stop(robot, kAllJoints);
  EXPECT_TRUE(d.stop);
  EXPECT_EQ(d.violating, joint_bit(kElbow) | joint_bit(kTrack));
  EXPECT_EQ(d.first_joint, kElbow);  // lower index first
  EXPECT_EQ(d.first.reason, FaultReason::velocity_limit);
}

TEST(SafeStop, LostJointsOutsideTheMonitoredSetAreIgnored) {
  RobotSample robot = all_inside();
  const JointMask lost = joints_lost_by_link_failure_at(kElbow);
  robot[kElbow].position_rad = std::nan("");  // stale or garbage data of an unreachable joint
  EXPECT_FALSE(decide_safe_stop(robot, kAllJoints & ~lost).stop);
  EXPECT_TRUE(decide_safe_stop(robot, kAllJoints).stop);
}

}  // namespace
}  // namespace rescue
