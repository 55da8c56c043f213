// One CiA 402 joint drive: the state machine (drivers/cia402/cia402.hpp) driven by the controlword, the
// cyclic synchronous modes CSP/CSV/CST (core/robot/robot.hpp ControlMode) and the motor behind it
// (drivers/sim/devices/joint_motor_model.hpp), with injectable faults. Stepped on virtual time, no heap.
//
// Per cycle the device hands it the outputs the master wrote (apply_outputs) and reads the
// inputs back (inputs); between cycles time passes (advance). Outside EtherCAT OP the outputs are
// not valid: the drive then sees "disable voltage" (its power stage switches off and the worm
// gear holds the joint), which is also what happens when the master stops refreshing them.
//
// Faults: following error in CSP (|target - actual| beyond 0x6065 for longer than 0x6066),
// and injected faults (over-temperature, ...). A fault runs the fault reaction (braking on the
// quick-stop ramp) then enters Fault with 0x603F set; a rising edge of controlword bit 7 resets
// it unless the fault's cause persists.
#pragma once

#include <cstdint>

#include "drivers/cia402/cia402.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "drivers/sim/devices/joint_motor_model.hpp"
#include "hal/time/clock.hpp"

namespace rescue::drivers {

// CiA 402 / CiA 301 error codes (0x603F) the drive raises.
namespace drive_error {
constexpr std::uint16_t kNone = 0x0000;
constexpr std::uint16_t kFollowingError = 0x8611;
constexpr std::uint16_t kOverTemperature = 0x4210;  // excess temperature, device
constexpr std::uint16_t kOverCurrent = 0x2310;      // continuous over-current
constexpr std::uint16_t kEncoder = 0x7305;          // incremental sensor 1 fault
constexpr std::uint16_t kCommunication = 0x8100;
}  // namespace drive_error

// The aperiodic settings the drive works with (object dictionary values).
struct DriveSettings {
  std::int32_t position_min_counts{0};     // 0x607D:01
  std::int32_t position_max_counts{0};     // 0x607D:02
  std::uint32_t max_velocity_counts_s{0};  // 0x607F
  std::uint16_t max_torque_per_mille{1000};  // 0x6072
  std::uint32_t following_error_window_counts{0};  // 0x6065
  std::uint16_t following_error_timeout_ms{0};     // 0x6066
};

constexpr std::uint32_t kPositionWindowCounts = 200;  // "target reached" in CSP (~1.2 mrad)

class Cia402Drive {
 public:
  Cia402Drive() noexcept = default;
  Cia402Drive(const MotorLimits& limits, double initial_position_rad) noexcept;

  // Power-up self test done: Not ready to switch on -> Switch on disabled.
  void power_up() noexcept;

  // The outputs of one cycle at time `now`; `valid` is false outside OP (treated as controlword 0).
  void apply_outputs(const JointOutputs& outputs, bool valid, const DriveSettings& settings, hal::Nanoseconds now) noexcept;
  // Time passes: the motor moves, ramps finish, following error is timed.
  void advance(hal::Nanoseconds dt, const DriveSettings& settings) noexcept;
  JointInputs inputs() const noexcept;

  // A fault from outside (fault injection, hardware). A persistent fault refuses the reset until
  // clear_fault_cause().
  void inject_fault(std::uint16_t error_code, bool persistent = false) noexcept;
  void clear_fault_cause() noexcept;

  cia402::State state() const noexcept { return machine_.state(); }
  const cia402::StateMachine& machine() const noexcept { return machine_; }
  const JointMotorModel& motor() const noexcept { return motor_; }
  std::uint16_t error_code() const noexcept { return error_code_; }

 private:
  MotorCommand motor_command(const DriveSettings& settings) noexcept;
  void raise(std::uint16_t error_code) noexcept;
  std::int32_t following_error_counts() const noexcept;

  cia402::StateMachine machine_{};
  JointMotorModel motor_{};
  JointOutputs outputs_{};
  ControlMode mode_{ControlMode::none};
  double target_position_rad_{0.0};
  double feed_forward_rad_s_{0.0};
  hal::Nanoseconds last_outputs_at_{-1};
  hal::Nanoseconds following_error_for_{0};
  std::uint16_t error_code_{drive_error::kNone};
  bool following_error_{false};
  bool target_clamped_{false};
  bool fault_cause_persists_{false};
  // motor_command()'s conversion of the settings' limits, and what it was converted from.
  bool limits_converted_{false};
  std::uint16_t converted_torque_per_mille_{0};
  std::uint32_t converted_velocity_counts_s_{0};
  double torque_limit_nm_{0.0};
  double velocity_limit_rad_s_{0.0};
};

}  // namespace rescue::drivers
