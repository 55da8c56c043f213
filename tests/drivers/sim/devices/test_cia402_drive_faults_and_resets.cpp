// Drive faults: an injected fault or a following error runs the fault reaction (braking within
// the torque limit), ends in Fault with the error code in 0x603F, and a fault reset (rising edge
// of controlword bit 7) clears it, unless the fault's cause persists.
#include <gtest/gtest.h>

#include <cmath>

#include "drivers/sim/devices/cia402_drive.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "drivers/joint/joint_units.hpp"

namespace rescue::drivers {
namespace {

constexpr hal::Nanoseconds kCycle = hal::kNsPerMs;

struct Harness {
  explicit Harness(const char* name)
      : joint(joint_index_by_name(name)), objects(joint, slave_position_of_joint(joint)), drive(motor_limits_of(joint), 0.0) {
    drive.power_up();
    out.mode_of_operation = static_cast<std::int8_t>(ControlMode::cyclic_velocity);
  }
  JointInputs cycle() {
    drive.apply_outputs(out, true, objects.settings(), now);
    drive.advance(kCycle, objects.settings());
    now += kCycle;
    return drive.inputs();
  }
  void enable_and_move(double rad_s) {
    for (std::uint16_t cw : {cia402::cw::kShutdown, cia402::cw::kSwitchOnCommand, cia402::cw::kEnableOperationCommand}) {
      out.controlword = cw;
      (void)cycle();
    }
    out.target_velocity = drivers::rad_to_counts(rad_s);
    for (int i = 0; i < 400; ++i) (void)cycle();
  }
  std::size_t joint;
  JointDriveObjects objects;
  Cia402Drive drive;
  JointOutputs out;
  hal::Nanoseconds now{0};
};

TEST(DriveFault, InjectedOverTemperatureBrakesThenFaultsWithItsErrorCode) {
  Harness h("r_elbow");
  h.enable_and_move(1.5);
  const double v0 = h.drive.motor().velocity_rad_s();
  ASSERT_GT(v0, 1.4);
  h.drive.inject_fault(drive_error::kOverTemperature);
  JointInputs in = h.drive.inputs();
  EXPECT_EQ(cia402::state_from_statusword(in.statusword), cia402::State::fault_reaction_active);
  EXPECT_EQ(in.error_code, drive_error::kOverTemperature);
  int cycles = 0;
  while (h.drive.state() == cia402::State::fault_reaction_active && cycles < 1000) {
    in = h.cycle();
    EXPECT_LE(std::abs(in.torque_actual), 1000);
    ++cycles;
  }
  EXPECT_EQ(h.drive.state(), cia402::State::fault);
  // Braking at the torque limit takes about v0 / a_max.
  EXPECT_NEAR(cycles * 1e-3, v0 / h.drive.motor().acceleration_limit(), 0.01);
  EXPECT_EQ(in.statusword & 0x004F, 0x0008);
  EXPECT_EQ(in.error_code, drive_error::kOverTemperature);
  EXPECT_EQ(in.velocity_actual, 0);
  const std::int32_t held = in.position_actual;
  for (int i = 0; i < 100; ++i) in = h.cycle();  // still asking for enable: Fault ignores it
  EXPECT_EQ(h.drive.state(), cia402::State::fault);
  EXPECT_EQ(in.position_actual, held);

  h.out.controlword = cia402::cw::kFaultResetCommand;
  in = h.cycle();
  EXPECT_EQ(h.drive.state(), cia402::State::switch_on_disabled);
  EXPECT_EQ(in.error_code, drive_error::kNone);
}

TEST(DriveFault, PersistentCauseRefusesTheResetUntilCleared) {
  Harness h("neck_pan");
  h.drive.inject_fault(drive_error::kEncoder, true);
  h.out.controlword = cia402::cw::kDisableVoltage;
  (void)h.cycle();
  EXPECT_EQ(h.drive.state(), cia402::State::fault);  // unpowered: the reaction ends at once
  h.out.controlword = cia402::cw::kFaultResetCommand;
  (void)h.cycle();
  EXPECT_EQ(h.drive.state(), cia402::State::fault);
  h.drive.clear_fault_cause();
  h.out.controlword = cia402::cw::kDisableVoltage;
  (void)h.cycle();
  h.out.controlword = cia402::cw::kFaultResetCommand;
  const JointInputs in = h.cycle();
  EXPECT_EQ(h.drive.state(), cia402::State::switch_on_disabled);
  EXPECT_EQ(in.error_code, 0);
}

TEST(DriveFault, CspFollowingErrorBeyondWindowAndTimeoutFaults) {
  Harness h("waist_yaw");
  h.out.mode_of_operation = static_cast<std::int8_t>(ControlMode::cyclic_position);
  for (std::uint16_t cw : {cia402::cw::kShutdown, cia402::cw::kSwitchOnCommand, cia402::cw::kEnableOperationCommand}) {
    h.out.controlword = cw;
    (void)h.cycle();
  }
  // A 2-rad jump: far outside the 0.5-rad window for longer than the 100-ms timeout.
  h.out.target_position = drivers::rad_to_counts(2.0);
  JointInputs in = h.cycle();
  EXPECT_NE(in.statusword & cia402::sw::kFollowingError, 0);
  for (int i = 0; i < 300 && h.drive.state() == cia402::State::operation_enabled; ++i) in = h.cycle();
  EXPECT_NE(h.drive.state(), cia402::State::operation_enabled);
  EXPECT_EQ(h.drive.error_code(), drive_error::kFollowingError);
}

}  // namespace
}  // namespace rescue::drivers
