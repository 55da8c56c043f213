// The mechanics behind one joint drive: a motor driving the joint through a self-locking worm
// gear, seen at the joint (output) side, stepped on virtual time.
//
//   powered       the drive's cascade: position loop (CSP) -> velocity loop -> torque, with the
//                 velocity saturated at the velocity limit, the torque at the torque limit and so
//                 the acceleration at torque / inertia. CST commands the torque directly.
//   braking       powered, decelerating at the quick-stop deceleration to standstill
//                 (quick stop, fault reaction)
//   unpowered     the worm gear is self-locking: the joint does not move (velocity 0), whatever
//                 the load; this is also what happens when the drive is unreachable
//
// The inertia is chosen so that the joint's torque limit gives it its acceleration limit
// (velocity limit reached in kAccelerationTime). Position is integrated in double radians and
// read out through a 2^20-counts/rev encoder (core/robot/robot.hpp); continuous joints (tracks) wrap.
// Pure arithmetic on a few doubles: no heap, no clock, deterministic.
#pragma once

#include <cstdint>

#include "core/robot/robot.hpp"
#include "hal/time/clock.hpp"

namespace rescue::drivers {

struct MotorLimits {
  double velocity_max_rad_s{1.0};
  double torque_max_nm{1.0};         // at the joint
  double rated_torque_nm{1.0};       // CiA 402 torques are per mille of this
  double position_min_rad{0.0};      // ignored for continuous joints
  double position_max_rad{0.0};
  bool continuous{false};
};

// Time to reach the velocity limit from standstill at full torque: sets the inertia.
constexpr double kAccelerationTime = 0.2;
// Loop gains of the drive's cascade (1/s): position -> velocity, velocity -> acceleration.
constexpr double kPositionGain = 25.0;
constexpr double kVelocityGain = 60.0;
// Integration step: finer than any cycle the master runs, coarse enough to stay cheap.
constexpr hal::Nanoseconds kMotorSubstepNs = 100 * hal::kNsPerUs;

enum class MotorDrive : std::uint8_t { unpowered, position, velocity, torque, braking };

struct MotorCommand {
  MotorDrive drive{MotorDrive::unpowered};
  double position_rad{0.0};   // position mode target
  double velocity_rad_s{0.0}; // velocity mode target / position mode feed-forward
  double torque_nm{0.0};      // torque mode target
  double torque_limit_nm{0.0};    // <= MotorLimits::torque_max_nm (0x6072)
  double velocity_limit_rad_s{0.0};  // <= MotorLimits::velocity_max_rad_s (0x607F)
};

class JointMotorModel {
 public:
  JointMotorModel() noexcept = default;
  JointMotorModel(const MotorLimits& limits, double initial_position_rad) noexcept;

  // Advances the mechanics by `dt` under `command`.
  void step(const MotorCommand& command, hal::Nanoseconds dt) noexcept;

  double position_rad() const noexcept { return position_; }
  double velocity_rad_s() const noexcept { return velocity_; }
  double torque_nm() const noexcept { return torque_; }
  double acceleration_limit() const noexcept { return acceleration_max_; }
  double inertia() const noexcept { return inertia_; }
  // True when the last step hit a position, velocity or torque limit.
  bool limited() const noexcept { return limited_; }
  bool standstill() const noexcept;
  const MotorLimits& limits() const noexcept { return limits_; }

  // Encoder: position in counts (wrapping through int32 like a modulo axis for continuous
  // joints), velocity in counts/s, torque in per mille of the rated torque.
  std::int32_t position_counts() const noexcept;
  std::int32_t velocity_counts_s() const noexcept;
  std::int16_t torque_per_mille() const noexcept;

 private:
  struct MotorState {
    double position;
    double velocity;
    double torque;
    bool limited;  // this substep hit a limit
  };
  void substep(const MotorCommand& command, double dt, MotorState& state) const noexcept;
  // True when a substep of `h` under `command` is known to leave the state as it is (rest_).
  bool rests_under(const MotorCommand& command, hal::Nanoseconds h) const noexcept;

  // The last substep left the state bit for bit unchanged: under which command, with which step,
  // and whether it hit a limit (a joint held still rests there until its command changes).
  struct Rest {
    bool known{false};
    MotorCommand command{};
    hal::Nanoseconds h{0};
    bool limited{false};
  };

  MotorLimits limits_{};
  double inertia_{1.0};
  double acceleration_max_{1.0};
  double position_{0.0};
  double velocity_{0.0};
  double torque_{0.0};
  bool limited_{false};
  Rest rest_{};
};

// The limits of joint `joint` from core/robot/robot.hpp.
MotorLimits motor_limits_of(std::size_t joint) noexcept;

}  // namespace rescue::drivers
