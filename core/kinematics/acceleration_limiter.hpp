// The last stage of every RC task's references: each joint follows what the task computed with its
// velocity and acceleration limits (kJoints velocity, the URDF's <limit acceleration>), so no
// reference the RC tasks write asks a drive for more.
//
// Per joint, every period: the wanted position x* and its rate v* (from the last wanted position);
// the velocity that closes the gap e = x* - x without overshoot, braking at a_max:
//   v_d = v* + sign(e) min(braking_speed(|e|), |e| / dt)      (about sqrt(2 a_max |e|))
// then v = v_d clamped to the interval every limit allows this period:
//   [v - a_max dt, v + a_max dt]  and  [-v_max, v_max]  and  [-braking_speed(x - x_min), braking_speed(x_max - x)]
// and x += v dt, never past the point where the wanted motion can still stop at a_max from its rate
// (x* + stopping_distance(v*), either way: a ramp closing a gap on a motion that then slows does not
// overshoot it and come back), as far as [v - a_max dt, v + a_max dt] allows. The last interval
// brakes in time for the position limits: a joint never moves
// faster than it can still stop before a limit at a_max, so it arrives at a limit at rest, whatever
// the wanted motion does (a blip, a reversal, a target beyond the limit). The three intervals always
// meet: a speed allowed last period is within a_max dt of one allowed now (braking_speed's sequence
// v, v - a_max dt, ... is what remains of the room). A wanted motion within the limits (the rescue
// motion's trajectory) passes unchanged (e stays 0); a jump (a new target, a mode change) becomes a
// ramp. Joints out of service hold where they are, with zero velocity (they are not commanded);
// joints asked to brake (a task that stops driving them while they move) come to rest at a_max and
// hold. Pure computation, fixed size.
//
// Jerk: a joint whose drive declares a jerk limit j_max (the URDF's optional <limit jerk>, kJointJerk)
// has its ramp smoothed by a moving average over N = ceil(2 a_max / (j_max dt)) periods, the drives'
// own "jerk filter": the average of positions whose acceleration is within +-a_max has an
// acceleration within +-a_max and a jerk (a_k - a_(k-N)) / (N dt) within j_max; its speed stays
// within v_max, it never goes beyond what it averages (no overshoot, within the position limits) and
// ends on the target N periods after the ramp does. The price: such a joint follows every motion
// (N - 1) dt / 2 late (0.1 s for the hands).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "core/kinematics/kinematic_model.hpp"

namespace rescue::kin {

// The highest speed from which a joint stops within `distance` braking at `a_max`, in periods of
// dt: n whole steps of a_max dt less each cover a_max dt^2 n (n + 1) / 2; what is left of the
// distance is spread evenly over those n + 1 periods (less than a_max dt more each), so the speed
// falls by exactly a_max dt per period (the continuous sqrt(2 a d) would ask for more than a_max
// in the last periods).
inline double braking_speed(double distance, double a_max, double dt_s) noexcept {
  const double step = a_max * dt_s;
  const double n = std::floor(std::sqrt(0.25 + 2.0 * distance / (step * dt_s)) - 0.5);
  const double left = distance - step * dt_s * n * (n + 1.0) / 2.0;
  return step * n + left / ((n + 1.0) * dt_s);
}

// How far a motion at `speed` (>= 0) goes after this period when its speed falls by a_max dt each
// period from the next: dt (n speed - a_max dt n (n + 1) / 2), n = floor(speed / (a_max dt)). The
// inverse of braking_speed: braking_speed(speed dt + stopping_distance(speed)) == speed.
inline double stopping_distance(double speed, double a_max, double dt_s) noexcept {
  const double step = a_max * dt_s;
  const double n = std::floor(speed / step);
  return dt_s * (n * speed - step * n * (n + 1.0) / 2.0);
}

// Joints with a jerk limit the limiter can hold, and its longest moving average (periods).
inline constexpr std::size_t kMaxJerkJoints = 4;
inline constexpr std::size_t kMaxJerkWindow = 512;

// Periods of the moving average that keeps a joint with acceleration limit a_max within j_max.
inline std::size_t jerk_window(double a_max, double j_max, double dt_s) noexcept {
  return static_cast<std::size_t>(std::ceil(2.0 * a_max / (j_max * dt_s) - 1e-9));
}

// The model's jerk limits fit the limiter at the RC period of 1 ms.
constexpr bool model_jerk_limits_fit() {
  std::size_t count = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (kJointJerk[j] == 0.0) continue;
    ++count;
    if (2.0 * kJointAcceleration[j] / (kJointJerk[j] * 0.001) > static_cast<double>(kMaxJerkWindow)) return false;
  }
  return count <= kMaxJerkJoints;
}
static_assert(model_jerk_limits_fit(),
              "a jerk limit in core/robot/rescue_robot.urdf needs more than kMaxJerkJoints joints or a longer window");

class AccelerationLimiter {
 public:
  // `jerk`: per joint, rad/s^3, 0 for none (default: the model's kJointJerk; at most kMaxJerkJoints
  // joints with one, each window at most kMaxJerkWindow periods, which kinematic_model.hpp checks
  // for the model at the 1 ms period; beyond, the extra joints or periods are ignored).
  // `braking`: per joint, the deceleration (rad/s^2) a braking joint comes to rest with, at most its
  // acceleration limit (default: that limit); near a position limit it brakes at up to that limit.
  AccelerationLimiter(const JointVector& start, double dt_s, const JointArray& jerk = kJointJerk,
                      const JointArray& braking = kJointAcceleration) noexcept;

  // Restarts at `position` at rest (a restart).
  void reset(const JointVector& position) noexcept;
  // Restarts at `position` moving at `velocity` (a new owner of the motion taking over the references
  // being sent and their speed: bumpless, its first references continue that motion within the
  // limits). A jerk-limited joint restarts at rest: its moving average runs (N - 1) / 2 periods
  // behind what it is asked, so no state continues a speed without a step back (no RC task's
  // limiter takes a hand at speed: the rescue task does not command the hands, the teleop task has
  // no such filter; the handler's intake, which smooths every reference, is never reset at speed).
  void reset(const JointVector& position, const JointVector& velocity) noexcept;
  // Restarts one joint at `position` at rest (another authority set its reference).
  void reset_joint(std::size_t joint, double position) noexcept;

  // Forgets the gap between what was wanted last period and the references: the next `wanted` is
  // taken as a motion from the references themselves (a task that plans from what is sent).
  void plan_from_references() noexcept;

  // One period towards `wanted`; returns the references. Joints in `braking` ignore `wanted`: they
  // come to rest at their acceleration limit (within the position limits) and then hold.
  const JointVector& step(const JointVector& wanted, JointMask out_of_service, JointMask braking = 0) noexcept;

  const JointVector& position() const noexcept { return position_; }
  const JointVector& velocity() const noexcept { return velocity_; }
  // Joints whose wanted motion was beyond a limit last period (the references lag it).
  JointMask limited() const noexcept { return limited_; }

 private:
  double dt_s_;
  JointArray braking_;
  JointVector position_;
  JointVector velocity_;
  JointVector last_wanted_;
  JointMask limited_{0};
  // Jerk-limited joints: the acceleration-limited ramp (the moving average's input) and its window.
  struct JerkFilter {
    std::size_t joint{0};
    std::size_t window{1};
    std::size_t head{0};
    double ramp_position{0.0};
    double ramp_velocity{0.0};
    std::size_t steady{0};  // periods the ramp has not moved (the window is settled once >= window - 1)
    std::array<double, kMaxJerkWindow> history{};
    void restart(double position) noexcept;  // at rest at `position`, the window filled with it
  };
  std::array<JerkFilter, kMaxJerkJoints> filters_{};
  std::size_t filter_count_{0};
  std::array<int, kJointCount> filter_of_{};  // index into filters_, -1: no jerk limit
};

}  // namespace rescue::kin
