// The joint drive's mechanics: a step in velocity, position or torque is followed without ever
// exceeding the joint's velocity, acceleration and torque limits (core/robot/robot.hpp); the worm gear
// holds the joint still when the drive is not powered or its outputs are no longer valid.
#include <gtest/gtest.h>

#include <cmath>

#include "core/robot/robot.hpp"
#include "drivers/sim/devices/cia402_drive.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "drivers/joint/joint_units.hpp"

namespace rescue::drivers {
namespace {

constexpr hal::Nanoseconds kCycle = hal::kNsPerMs;

struct DriveUnderTest {
  explicit DriveUnderTest(const char* name)
      : joint(joint_index_by_name(name)),
        objects(joint, slave_position_of_joint(joint)),
        drive(motor_limits_of(joint), 0.0) {
    drive.power_up();
  }
  // One 1-ms cycle: outputs in, time passes, inputs out.
  JointInputs cycle(const JointOutputs& out, bool valid = true) {
    drive.apply_outputs(out, valid, objects.settings(), now);
    drive.advance(kCycle, objects.settings());
    now += kCycle;
    return drive.inputs();
  }
  void enable(ControlMode mode) {
    JointOutputs out;
    out.mode_of_operation = static_cast<std::int8_t>(mode);
    out.target_position = drive.inputs().position_actual;
    for (std::uint16_t cw : {cia402::cw::kShutdown, cia402::cw::kSwitchOnCommand, cia402::cw::kEnableOperationCommand}) {
      out.controlword = cw;
      (void)cycle(out);
    }
    ASSERT_EQ(drive.state(), cia402::State::operation_enabled);
  }
  // Outputs of an enabled drive in `mode` (targets zero).
  static JointOutputs operating(ControlMode mode) {
    JointOutputs out;
    out.controlword = cia402::cw::kEnableOperationCommand;
    out.mode_of_operation = static_cast<std::int8_t>(mode);
    return out;
  }
  std::size_t joint;
  JointDriveObjects objects;
  Cia402Drive drive;
  hal::Nanoseconds now{0};
};

TEST(JointMotorModel, VelocityStepWithinVelocityAccelerationAndTorqueLimits) {
  const MotorLimits limits = motor_limits_of(joint_index_by_name("waist_yaw"));
  JointMotorModel motor(limits, 0.0);
  MotorCommand c;
  c.drive = MotorDrive::velocity;
  c.velocity_rad_s = 0.8;
  c.torque_limit_nm = limits.torque_max_nm;
  c.velocity_limit_rad_s = limits.velocity_max_rad_s;
  double previous_v = 0.0;
  double max_accel = 0.0;
  for (int i = 0; i < 1000; ++i) {
    motor.step(c, kCycle);
    max_accel = std::max(max_accel, std::fabs(motor.velocity_rad_s() - previous_v) / 1e-3);
    previous_v = motor.velocity_rad_s();
    EXPECT_LE(std::fabs(motor.velocity_rad_s()), limits.velocity_max_rad_s + 1e-9);
    EXPECT_LE(std::fabs(motor.torque_nm()), limits.torque_max_nm + 1e-9);
  }
  EXPECT_NEAR(motor.velocity_rad_s(), 0.8, 1e-3);
  EXPECT_LE(max_accel, motor.acceleration_limit() * 1.0001);
  EXPECT_GT(max_accel, 0.9 * motor.acceleration_limit());  // the step saturates the torque first
  EXPECT_NEAR(motor.acceleration_limit(), limits.velocity_max_rad_s / kAccelerationTime, 1e-9);
  EXPECT_EQ(motor.velocity_counts_s(), static_cast<std::int32_t>(std::lround(0.8 * drivers::kCountsPerRad)));
}

TEST(JointMotorModel, CommandAboveTheVelocityLimitIsClampedAndFlagged) {
  const MotorLimits limits = motor_limits_of(joint_index_by_name("l_track"));
  JointMotorModel motor(limits, 0.0);
  MotorCommand c;
  c.drive = MotorDrive::velocity;
  c.velocity_rad_s = 100.0;
  c.torque_limit_nm = limits.torque_max_nm;
  c.velocity_limit_rad_s = limits.velocity_max_rad_s;
  for (int i = 0; i < 2000; ++i) motor.step(c, kCycle);
  EXPECT_NEAR(motor.velocity_rad_s(), limits.velocity_max_rad_s, 1e-9);
  EXPECT_TRUE(motor.limited());
}

TEST(Cia402Drive, CspPositionStepIsReachedWithoutExceedingTheVelocityLimit) {
  DriveUnderTest t("l_elbow");
  t.enable(ControlMode::cyclic_position);
  JointOutputs out = DriveUnderTest::operating(ControlMode::cyclic_position);
  out.target_position = drivers::rad_to_counts(0.3);
  const std::int32_t vmax_counts = drivers::rad_to_counts(kJoints[t.joint].limits.velocity_max_rad_s);
  JointInputs in;
  bool reached = false;
  for (int i = 0; i < 2000 && !reached; ++i) {
    in = t.cycle(out);
    EXPECT_LE(std::abs(in.velocity_actual), vmax_counts + 1);
    EXPECT_LE(std::abs(in.torque_actual), 1000);
    EXPECT_EQ(in.statusword & cia402::sw::kFollowingError, 0) << i;  // 0.3 rad stays inside the window
    reached = (in.statusword & cia402::sw::kTargetReached) != 0;
  }
  EXPECT_TRUE(reached);
  EXPECT_NEAR(in.position_actual, out.target_position, kPositionWindowCounts);
  EXPECT_EQ(in.mode_display, static_cast<std::int8_t>(ControlMode::cyclic_position));
  EXPECT_EQ(cia402::state_from_statusword(in.statusword), cia402::State::operation_enabled);
  EXPECT_NE(in.statusword & cia402::sw::kFollowsCommand, 0);
}

TEST(Cia402Drive, CspTargetBeyondTheSoftwareLimitStopsAtTheLimit) {
  DriveUnderTest t("neck_tilt");  // -0.8 .. 1.0 rad
  t.enable(ControlMode::cyclic_position);
  JointOutputs out = DriveUnderTest::operating(ControlMode::cyclic_position);
  JointInputs in;
  // Walk the target past the upper limit slowly (no following error), then hold it there.
  for (int i = 0; i < 3000; ++i) {
    out.target_position = drivers::rad_to_counts(std::min(1.5, 0.001 * i));
    in = t.cycle(out);
  }
  EXPECT_NEAR(drivers::counts_to_rad(in.position_actual), 1.0, 1e-3);
  EXPECT_NE(in.statusword & cia402::sw::kInternalLimitActive, 0);
}

TEST(Cia402Drive, CstTorqueStepAcceleratesUpToTheVelocityLimit) {
  DriveUnderTest t("r_track");
  t.enable(ControlMode::cyclic_torque);
  JointOutputs out = DriveUnderTest::operating(ControlMode::cyclic_torque);
  out.target_torque = 500;  // half the rated torque
  JointInputs in = t.cycle(out);
  EXPECT_EQ(in.torque_actual, 500);
  for (int i = 0; i < 3000; ++i) in = t.cycle(out);
  EXPECT_NEAR(in.velocity_actual, drivers::rad_to_counts(kJoints[t.joint].limits.velocity_max_rad_s), 2);
  EXPECT_NE(in.statusword & cia402::sw::kInternalLimitActive, 0);
}

TEST(WormGear, HoldsTheJointWhenTheDriveIsSwitchedOff) {
  DriveUnderTest t("r_shoulder_pitch");
  t.enable(ControlMode::cyclic_velocity);
  JointOutputs out = DriveUnderTest::operating(ControlMode::cyclic_velocity);
  out.target_velocity = drivers::rad_to_counts(1.0);
  for (int i = 0; i < 500; ++i) (void)t.cycle(out);
  ASSERT_GT(t.drive.motor().velocity_rad_s(), 0.9);
  out.controlword = cia402::cw::kDisableVoltage;
  JointInputs in = t.cycle(out);
  EXPECT_EQ(t.drive.state(), cia402::State::switch_on_disabled);
  EXPECT_EQ(in.velocity_actual, 0);
  const std::int32_t held = in.position_actual;
  for (int i = 0; i < 5000; ++i) in = t.cycle(out);  // 5 s, target velocity still set
  EXPECT_EQ(in.position_actual, held);
  EXPECT_EQ(in.torque_actual, 0);
}

TEST(WormGear, HoldsTheJointWhenOutputsStopBeingValid) {
  DriveUnderTest t("l_leg");
  t.enable(ControlMode::cyclic_velocity);
  JointOutputs out = DriveUnderTest::operating(ControlMode::cyclic_velocity);
  out.target_velocity = drivers::rad_to_counts(-0.5);
  for (int i = 0; i < 300; ++i) (void)t.cycle(out);
  ASSERT_LT(t.drive.motor().velocity_rad_s(), -0.4);
  JointInputs in = t.cycle(out, false);  // the master is gone (SAFE-OP, watchdog)
  EXPECT_EQ(t.drive.state(), cia402::State::switch_on_disabled);
  const std::int32_t held = in.position_actual;
  for (int i = 0; i < 2000; ++i) in = t.cycle(out, false);
  EXPECT_EQ(in.position_actual, held);
  EXPECT_EQ(in.velocity_actual, 0);
}

}  // namespace
}  // namespace rescue::drivers
