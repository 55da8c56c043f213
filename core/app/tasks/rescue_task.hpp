// The rescue RC task: its references every period, in the RC task frame (rc_task_frame.hpp: joints,
// inputs, ownership, reference space, heartbeat).
//   Taking the motion starts the rescue motion from the references being sent (their positions and
//   speeds: a joint moving at the take brakes within its limits): a minimum-jerk joint-space
//   approach to kin::ready_posture(), then kin::RcPeriod (lowering, forwarding, backwarding through
//   the task-priority IK); after it, the end pose is held. An end-effector target (`ctl move`)
//   moves that palm there (IK), the other palm held. Joints out of service are locked and left out
//   of the solution. Every reference respects the joints' velocity and acceleration limits
//   (kin::AccelerationLimiter). Hand inputs are teleoperation's: counted as ignored.
// It measures what it drives while it owns the motion (RcTaskState: speeds, accelerations,
// symmetry, path deviation, COM margin, travel after a loss). No heap after construction.
#pragma once

#include <array>
#include <cstdint>

#include "core/app/tasks/rc_task_frame.hpp"
#include "core/kinematics/acceleration_limiter.hpp"
#include "core/kinematics/rc_period.hpp"
#include "core/kinematics/task_priority_ik.hpp"

namespace rescue::app {

struct RescueTaskSettings {
  hal::Nanoseconds period_ns{0};           // config::kRcTaskPeriodNs
  double approach_s{1.6};                   // joint-space move to the ready posture (at least;
                                            // longer when a joint's limits need it)
  kin::RescueMotionConfig motion{};         // the phases
};
RescueTaskSettings default_rescue_task_settings() noexcept;

class RescueTask {
 public:
  // Every port must be non-null; they are the rescue task's (RcTaskId::rescue).
  RescueTask(const RcTaskPorts& ports, const RescueTaskSettings& settings) noexcept;

  // One period at `now` (the tasks' common monotonic clock).
  // Out of line: the symbol toolchain/rt-verify.json names as this task's period entry.
  void period(hal::Nanoseconds now) noexcept;

  RcMode mode() const noexcept { return mode_; }
  bool owns() const noexcept { return frame_.owns(); }
  JointMask out_of_service() const noexcept { return frame_.out_of_service(); }
  const RcTaskCounters& counters() const noexcept { return frame_.counters(); }
  const kin::JointVector& references() const noexcept { return frame_.references(); }
  kin::RescuePhase rescue_phase() const noexcept { return phase_; }

 private:
  friend class RcTaskFrame;  // calls the steps below
  void on_first_joints() noexcept { previous_ = frame_.sent(); }
  void on_input(const RcTaskInput& input) noexcept;
  void on_take(hal::Nanoseconds now) noexcept;
  void on_released() noexcept { mode_ = RcMode::idle; }
  void compute(hal::Nanoseconds now) noexcept;
  JointMask commanded() const noexcept;
  void after_publish() noexcept;
  void show(RcTaskState& state) const noexcept;

  void start_target(const RcTaskInput& input) noexcept;
  void approach(hal::Nanoseconds now) noexcept;
  void run_rescue_motion(hal::Nanoseconds now) noexcept;
  void move_to_target() noexcept;
  void measure() noexcept;
  void measure_speeds(bool driving) noexcept;
  void measure_after_loss(double waist, std::uint8_t damaged) noexcept;

  // Members by alignment (the kinematics' Eigen members first): no padding between them.
  kin::RcPeriod rescue_;
  kin::IkTargets targets_;
  kin::TaskPriorityIk ik_;
  kin::AccelerationLimiter limiter_;  // every mode's references within the joints' limits
  RcTaskFrame frame_;
  RescueTaskSettings settings_;
  kin::JointVector wanted_;           // what the mode computed, before the limiter
  kin::JointVector previous_;         // last period's references
  kin::JointVector approach_from_;
  kin::JointVector next_;
  kin::JointVector speed_;            // last period's reference speeds
  kin::IkStepReport ik_report_{};
  RcTaskState figures_{};             // speeds, accelerations, symmetry, COM margin (measure())
  std::array<kin::Vector3, 2> palm_at_loss_{kin::Vector3::Zero(), kin::Vector3::Zero()};
  double approach_s_{0.0};            // this approach's duration (the limits may lengthen it)
  double waist_at_loss_{0.0};         // the waist's reference when an arm was first damaged
  hal::Nanoseconds mode_since_{0};
  JointMask measured_{0};             // joints whose speed was measured last period
  RcMode mode_{RcMode::idle};
  kin::RescuePhase phase_{kin::RescuePhase::lowering};
};

}  // namespace rescue::app
