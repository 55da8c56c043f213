// The EtherCAT handler's side of the Motion owner (docs/motion-owner.md). Once per handler period,
// never blocking, it decides each position-mode joint's reference:
//   - the owner's references, if its reference space holds a complete period written under the
//     current owner word and completed within kOwnerReferenceDeadlineNs; only the joints they
//     command that the handler drives (enabled, reachable, not excluded) take them, through the same
//     limiter as the RC tasks' (kin::AccelerationLimiter): every reference sent keeps the joint's
//     position limits (braking in time), velocity and acceleration limits and, where the joint
//     declares one, its jerk limit, whatever the owner asks (an operator's `move`, `hand`, teleop, a
//     change of owner while a joint moves);
//   - otherwise the period counts as an owner miss, and each joint the owner had in motion is brought
//     to rest from its reference's velocity within its deceleration limit (the smaller of
//     deceleration_limit_rad_s2, core/robot/robot.hpp, and its acceleration limit), then holds: no
//     abrupt reference stop;
//   - an owner whose heartbeat is older than kOwnerDeadAfterPeriods RC periods is released
//     (compare-exchange on the word it saw) in the period the handler notices it, once the handler
//     itself has also run that many periods without seeing the heartbeat move: a stall of the whole
//     host (every task, the handler too, held off its CPU) is jitter, not a dead owner;
//   - while nobody owns the motion, each joint comes to rest the same way and holds the reference
//     last sent; a joint the joint manager gives a new reference (set reference, hold, initialize) or
//     does not drive takes the joint manager's (at once: the joint manager is the authority).
// A non-owner's reference space is never read. No heap, no locks, bounded work.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "core/app/links/motion_links.hpp"
#include "core/kinematics/acceleration_limiter.hpp"
#include "core/robot/joint_demand.hpp"
#include "core/robot/joint_fault.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

struct MotionIntakeSettings {
  hal::Nanoseconds reference_deadline_ns{0};  // config::kOwnerReferenceDeadlineNs
  hal::Nanoseconds owner_dead_after_ns{0};    // config::kOwnerDeadAfterPeriods * config::kRcTaskPeriodNs
  hal::Nanoseconds handler_period_ns{0};      // the velocity clamp's step
  // true: a joint the owner no longer drives comes to rest within its deceleration limit; false: its
  // reference stops where it is (the behaviour before issue 21, kept to measure the difference).
  bool ramped_hold{true};
  // true: every owner reference through the limiter; false: sent as the owner wrote it (a defect
  // kept to prove that the handler's check of what is sent stops the robot; tests only).
  bool limit_references{true};
};
MotionIntakeSettings default_intake_settings() noexcept;

// What the intake reaches of the motion's shared state (TaskLinks::motion, rc_heartbeat_ns), each at
// the end it uses: it reads the reference spaces (the owner's only) and the RC tasks' heartbeats,
// reads the owner word and releases a dead owner (compare-exchange), and publishes its counters.
// Built with the other tasks' ports (core/app/runtime/task_ports.hpp).
struct MotionIntakePorts {
  const std::array<ReferenceSpace, protocol::kMaxRcTasks>* references{nullptr};
  MotionOwner* owner{nullptr};
  const std::array<std::atomic<std::int64_t>, protocol::kMaxRcTasks>* rc_heartbeat_ns{nullptr};
  std::atomic<std::uint64_t>* owner_misses{nullptr};    // handler periods the owner's references were late or incomplete
  std::atomic<std::uint64_t>* owner_releases{nullptr};  // dead owners released
  std::atomic<JointMask>* owner_joints{nullptr};        // joints the owner's references drove last period
};

struct MotionIntakeCounters {
  std::uint64_t periods{0};
  std::uint64_t owned_periods{0};   // periods with an owner
  std::uint64_t used_periods{0};    // periods the owner's references were taken
  std::uint64_t misses{0};          // periods with an owner whose references were late, incomplete or not its own
  std::uint64_t incomplete{0};      // of the misses: no complete period (torn, never written, writer died mid-write)
  std::uint64_t stale{0};           // of the misses: completed longer ago than the deadline
  std::uint64_t foreign{0};         // of the misses: written under another owner word
  std::uint64_t releases{0};        // dead owners released
  std::uint64_t clamped{0};         // joint references limited (position, velocity, acceleration or jerk limit)
  std::uint64_t damaged_beats{0};   // the owner's heartbeat read damaged (links/heartbeat.hpp), each distinct value once
};

// What the intake sent, per joint, over the periods the joint was driven and kept its reference's
// history (a joint the joint manager set anew starts over): the largest speed, acceleration and jerk
// (the `run` report's joint-limit verdict: what the drives were sent, after every limit).
struct SentMotionFigures {
  std::array<double, kJointCount> max_speed_rad_s{};
  std::array<double, kJointCount> max_acceleration_rad_s2{};
  std::array<double, kJointCount> max_jerk_rad_s3{};
};

class MotionIntake {
 public:
  MotionIntake(const MotionIntakePorts& ports, const MotionIntakeSettings& settings) noexcept;

  // One handler period at `now`: `demand` is the joint manager's, `driven` the joints the handler
  // drives this period. Returns every joint's position reference (rad).
  const std::array<double, kJointCount>& period(hal::Nanoseconds now, const RobotDemand& demand, JointMask driven) noexcept;

  // `joint` stands at `position_rad` and is to hold there from now on (a drive enabled again after
  // its watchdog stopped it): its reference becomes that position, at rest.
  void rest_at(std::size_t joint, double position_rad) noexcept {
    limiter_.reset_joint(joint, position_rad);
    held_[joint] = position_rad;
    history_[joint] = 0;
  }

  // The speed of `joint`'s reference sent this period (rad/s; 0 for a joint not driven, or set anew
  // by the joint manager), within its speed limit: what a new owner continues from (the handler
  // publishes it as JointSample::velocity_ref_rad_s).
  double sent_speed(std::size_t joint) const noexcept;

  const MotionIntakeCounters& counters() const noexcept { return counters_; }
  const SentMotionFigures& sent_figures() const noexcept { return sent_; }
  // The first reference sent beyond a limit (speed, acceleration, jerk; none while every one kept
  // them): a defect of the limits, which the handler answers with its safe stop.
  std::size_t violating_joint() const noexcept { return violating_joint_; }
  const JointFault& violation() const noexcept { return violation_; }
  // The owner task whose references drove the joints last period (kNoOwnerTask: none, or held).
  std::uint8_t driving_task() const noexcept { return driving_; }
  std::uint64_t consecutive_misses() const noexcept { return consecutive_misses_; }
  // The joints the owner's references drove last period (also published: MotionLinks::owner_joints).
  JointMask owner_joints() const noexcept { return driven_by_owner_; }

 private:
  void decide(hal::Nanoseconds now, const RobotDemand& demand, JointMask driven) noexcept;
  bool take_owner_references(hal::Nanoseconds now, std::uint64_t word, JointMask driven) noexcept;
  // Every driven joint through the limiter: the owner's fresh references, the rest braking to rest.
  void limit(JointMask driven) noexcept;
  void measure(JointMask driven) noexcept;

  MotionIntakePorts ports_;
  MotionIntakeSettings settings_;
  kin::AccelerationLimiter limiter_;                // every reference sent (the RC tasks' limiter)
  kin::JointVector wanted_;                         // the owner's references taken (its last fresh ones)
  std::array<double, kJointCount> held_{};          // the references sent last period
  std::array<double, kJointCount> manager_ref_{};   // the joint manager's reference seen last period
  std::array<bool, kJointCount> driven_before_{};
  // Measuring what is sent: the last two speeds and the periods of history each joint has.
  std::array<double, kJointCount> previous_sent_{};
  std::array<double, kJointCount> speed_{};
  std::array<double, kJointCount> acceleration_{};
  std::array<std::uint8_t, kJointCount> history_{};
  SentMotionFigures sent_{};
  std::size_t violating_joint_{kJointCount};
  JointFault violation_{};
  ReferenceSnapshot snapshot_{};
  MotionIntakeCounters counters_{};
  std::uint64_t consecutive_misses_{0};
  // Each RC task's heartbeat as this handler last saw it, and how many of the handler's own periods
  // it has stayed there: the owner's silence in periods the handler actually ran.
  std::array<std::int64_t, protocol::kMaxRcTasks> beat_seen_{};
  std::array<std::int64_t, protocol::kMaxRcTasks> periods_beat_unchanged_{};
  JointMask driven_by_owner_{0};
  JointMask fresh_{0};                          // joints that took a new owner reference this period
  JointMask manager_set_{0};                    // joints that took the joint manager's reference this period
  hal::Nanoseconds taken_completed_ns_{0};      // the owner period taken last (its completion time)
  std::uint64_t taken_word_{0};
  std::uint8_t driving_{kNoOwnerTask};
};

}  // namespace rescue::app
