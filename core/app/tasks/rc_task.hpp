// An RC task (design brief section 3, paper IV-A): every period, at its own rate, whether or not it
// owns the motion, it
//   1. reads the joints (ports.samples: the references the handler sends, reachability) and
//      which joints are out of service (ports.joint_status: recorded lost or in Error; or unreachable);
//   2. takes its inputs from its queue (ports.inputs, filled by the message parser):
//      take_ownership (`ctl owner TASK`), end-effector targets (`ctl move`), hand open/close;
//   3. computes its references (kinematics, core/kinematics/):
//        rescue  taking the motion starts the rescue motion from the references being sent (their
//                positions and speeds: a joint moving at the take brakes within its limits): a
//                minimum-jerk joint-space approach to kin::ready_posture(), then kin::RcPeriod
//                (lowering, forwarding, backwarding through the task-priority IK); after it, the
//                end pose is held. An end-effector target moves that palm there (IK), the other
//                palm held. Joints out of service are locked and left out of the solution.
//        teleop  joint-space teleoperation (kin::JointSpaceTeleop): the hands open or close at a
//                fixed speed; taking the motion continues from the references being sent and their
//                speeds (with no command a moving joint brakes at its acceleration limit).
//      Every reference respects the joints' velocity and acceleration limits (the rescue task's
//      through kin::AccelerationLimiter, teleoperation's in kin::JointSpaceTeleop).
//   4. writes them into its own reference space (ports.references) under the
//      Motion owner word it holds (0 when it does not own the motion) and beats its heartbeat.
// Ownership: `ctl owner TASK` takes the motion (from whoever holds it). If the EtherCAT handler
// released it because this task fell silent (a stall) and nobody took it since, the task takes it
// back (compare-exchange on the free word) and goes on; a restarted task process starts without
// the operator's choice and waits for `ctl owner` again (if its killed predecessor's word is still
// there, the handler not having noticed the death yet, it frees it in its first period).
// Only the owner's references reach the joints (the EtherCAT handler's MotionIntake).
// The task sees only its ports (RcTaskPorts), so the same code runs as a thread (`run --threads`)
// or as its own process over the shared-memory segment. No heap after construction, no locks, bounded work.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "core/app/links/control_messages.hpp"
#include "core/app/links/joint_messages.hpp"
#include "core/app/links/motion_links.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/kinematics/acceleration_limiter.hpp"
#include "core/kinematics/rc_period.hpp"
#include "core/kinematics/task_priority_ik.hpp"
#include "core/robot/joint_sample.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

enum class RcMode : std::uint8_t { idle, approach, rescue_motion, target, teleop };
const char* to_string(RcMode mode) noexcept;

struct RcTaskSettings {
  RcTaskId id{RcTaskId::rescue};
  hal::Nanoseconds period_ns{0};           // config::kRcTaskPeriodNs
  double approach_s{1.6};                   // rescue: joint-space move to the ready posture (at least;
                                            // longer when a joint's limits need it)
  kin::RescueMotionConfig motion{};         // rescue: the phases
  double hand_speed_rad_s{0.5};             // teleop: hands open / close at this speed
};
RcTaskSettings default_rc_task_settings(RcTaskId id) noexcept;

struct RcTaskCounters {
  std::uint64_t periods{0};
  std::uint64_t owned_periods{0};
  std::uint64_t inputs{0};
  std::uint64_t ignored_inputs{0};    // inputs this task does not handle (e.g. a target to teleop)
  std::uint64_t takes{0};             // the operator gave it the motion
  std::uint64_t ownership_lost{0};    // another task took it, or the handler released it
  std::uint64_t retakes{0};           // took the motion back after a release while it was silent
  std::uint64_t predecessor_releases{0};  // freed the word a killed predecessor process held
  std::uint64_t kinematics_errors{0}; // periods whose kinematics refused its inputs (references held)
  std::uint64_t no_samples{0};        // periods before the handler published any joint
};

// What an RC task reaches of the tasks' shared state, each at the end it uses (built with the other
// tasks' ports, core/app/runtime/task_ports.hpp): its own input queue, reference space, state and
// heartbeat; the joints and their status; the owner word (taken and released by compare-exchange).
struct RcTaskPorts {
  const Seqlock<RobotSample>* samples{nullptr};           // the EtherCAT handler's joints
  const Seqlock<RobotJointStatus>* joint_status{nullptr};  // the joint manager's (lost, in Error)
  MessageSource<RcTaskInput>* inputs{nullptr};            // from the message parser
  MotionOwner* owner{nullptr};
  ReferenceSpace* references{nullptr};                    // its own, read by the handler's intake
  Seqlock<RcTaskState>* state{nullptr};                   // what it shows of itself (ctl owner, the run's report)
  std::atomic<std::int64_t>* heartbeat_ns{nullptr};       // monotonic ns of its latest period
};

class RcTask {
 public:
  // Every port must be non-null; they are the ports of task `settings.id`.
  RcTask(const RcTaskPorts& ports, const RcTaskSettings& settings) noexcept;

  // One period at `now` (the tasks' common monotonic clock).
  void period(hal::Nanoseconds now) noexcept;

  RcTaskId id() const noexcept { return settings_.id; }
  std::size_t index() const noexcept { return static_cast<std::size_t>(settings_.id); }
  RcMode mode() const noexcept { return mode_; }
  bool owns() const noexcept { return owns_; }
  JointMask out_of_service() const noexcept { return out_of_service_; }
  const RcTaskCounters& counters() const noexcept { return counters_; }
  const kin::JointVector& references() const noexcept { return references_; }
  kin::RescuePhase rescue_phase() const noexcept { return phase_; }

 private:
  void read_joints() noexcept;
  void take_inputs() noexcept;
  void on_take(hal::Nanoseconds now) noexcept;
  void start_target(const RcTaskInput& input) noexcept;
  void compute(hal::Nanoseconds now) noexcept;
  void publish(hal::Nanoseconds now, std::uint64_t word) noexcept;
  void measure() noexcept;
  JointMask commanded() const noexcept;

  RcTaskPorts ports_;
  RcTaskSettings settings_;
  kin::RcPeriod rescue_;
  kin::TaskPriorityIk ik_;
  kin::JointSpaceTeleop teleop_;
  kin::AccelerationLimiter limiter_;  // rescue: every mode's references within the joints' limits
  kin::JointVector wanted_;           // rescue: what the mode computed, before the limiter
  double approach_s_{0.0};            // rescue: this approach's duration (the limits may lengthen it)
  kin::JointVector references_;
  kin::JointVector previous_;
  kin::JointVector sent_;        // what the handler sends (samples' position_ref_rad)
  kin::JointVector sent_speed_;  // and its speed (samples' velocity_ref_rad_s)
  kin::JointVector approach_from_;
  kin::JointVector next_;
  kin::JointVector teleop_velocity_;
  kin::IkTargets targets_;
  kin::IkStepReport ik_report_{};
  RobotSample sample_{};
  RobotJointStatus status_{};
  RcTaskCounters counters_{};
  RcTaskState figures_{};             // rescue: speeds, accelerations, symmetry, COM margin (measure())
  kin::JointVector speed_;            // last period's reference speeds
  JointMask measured_{0};             // joints whose speed was measured last period
  double waist_at_loss_{0.0};         // rescue: the waist's reference when an arm was first damaged
  std::array<kin::Vector3, 2> palm_at_loss_{kin::Vector3::Zero(), kin::Vector3::Zero()};
  hal::Nanoseconds mode_since_{0};
  JointMask out_of_service_{0};
  RcMode mode_{RcMode::idle};
  kin::RescuePhase phase_{kin::RescuePhase::lowering};
  bool owns_{false};
  bool have_joints_{false};
  bool chosen_{false};
  bool take_pending_{false};  // the operator gave this task the motion (this process's life), nobody else since
};

}  // namespace rescue::app
