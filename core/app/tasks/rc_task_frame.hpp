// The frame every RC task runs in (design brief section 3, paper IV-A). Every period, at its own
// rate, whether or not it owns the motion, an RC task
//   1. reads the joints (ports.samples: the references the handler sends, reachability) and
//      which joints are out of service (ports.joint_status: recorded lost or in Error; or unreachable);
//   2. takes its inputs from its queue (ports.inputs, filled by the message parser):
//      take_ownership (`ctl owner TASK`) here, the others (end-effector targets, hand open/close) by
//      the task;
//   3. computes its references: the task's own kinematics (RescueTask, rescue_task.hpp;
//      TeleopTask, teleop_task.hpp);
//   4. writes them into its own reference space (ports.references) under the Motion owner word it
//      holds (0 when it does not own the motion), shows its state and beats its heartbeat.
// Ownership: `ctl owner TASK` takes the motion (from whoever holds it). If the EtherCAT handler
// released it because this task fell silent (a stall) and nobody took it since, the task takes it
// back (compare-exchange on the free word) and goes on; a restarted task process starts without
// the operator's choice and waits for `ctl owner` again (if its killed predecessor's word is still
// there, the handler not having noticed the death yet, it frees it in its first period).
// Only the owner's references reach the joints (the EtherCAT handler's MotionIntake).
// The task sees only its ports (RcTaskPorts), so the same code runs as a thread (`run --threads`)
// or as its own process over the shared-memory segment. No heap after construction, no locks,
// bounded work. The frame calls the task's steps through a template, bound at compile time: no
// virtual call, and the stack check (toolchain/rt-verify.json) follows every call.
#pragma once

#include <atomic>
#include <cstdint>

#include "core/app/config/firmware_config.hpp"
#include "core/app/links/control_messages.hpp"
#include "core/app/links/joint_messages.hpp"
#include "core/app/links/motion_links.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/kinematics/kinematic_model.hpp"
#include "core/robot/joint_sample.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

enum class RcMode : std::uint8_t { idle, approach, rescue_motion, target, teleop };
const char* to_string(RcMode mode) noexcept;

// An input is a record of the shared segment (the parser's queue to this task): a kind, effector or
// hand action the parser never writes, or a pose the operator's protocol refuses (not finite,
// beyond the robot's reach, an angle outside [-pi, pi]), is damage (a stray write, a bit flip).
bool rc_input_whole(const RcTaskInput& input) noexcept;

struct RcTaskCounters {
  std::uint64_t periods{0};
  std::uint64_t owned_periods{0};
  std::uint64_t inputs{0};
  std::uint64_t ignored_inputs{0};    // inputs this task does not handle (e.g. a target to teleop)
  std::uint64_t damaged_inputs{0};    // inputs refused as damaged records of the segment (rc_input_whole)
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

// The part of a period every RC task shares: the joints, the take, the owner word, the reference
// space, the state and the heartbeat. The task (a member of it) holds one and calls period(*this, now).
class RcTaskFrame {
 public:
  // Every port must be non-null; they are the ports of task `id`.
  RcTaskFrame(const RcTaskPorts& ports, RcTaskId id) noexcept;

  // One period at `now` (the tasks' common monotonic clock) of `task`, whose steps are:
  //   on_first_joints()    the handler's first joints arrived (references() holds them)
  //   on_input(input)      an input other than take_ownership
  //   on_take(now)         the operator gave it the motion (references() holds what is sent)
  //   on_released()        it lost the motion and the operator's choice no longer stands
  //   compute(now)         this period's references() (only once joints are known)
  //   commanded()          the joints it commands
  //   after_publish()      after the references are written
  //   show(state)          its mode, phase, figures and residuals into the state it shows
  template <typename Task>
  void period(Task& task, hal::Nanoseconds now) noexcept {
    ++counters_.periods;
    if (read_joints()) task.on_first_joints();
    take_inputs(task);
    if (take_pending_ && have_joints_) {
      take_pending_ = false;
      ++counters_.takes;
      references_ = sent_;  // bumpless: continue from what the handler sends, at the speed it sends it
      task.on_take(now);
    }
    const std::uint64_t word = settle_ownership();
    if (released_) task.on_released();
    if (have_joints_) {
      task.compute(now);
      publish_references(now, word, task.commanded());
      task.after_publish();
    } else {
      ++counters_.no_samples;
    }
    RcTaskState state{};
    task.show(state);
    publish_state(now, state);
  }

  std::size_t index() const noexcept { return static_cast<std::size_t>(id_); }
  bool owns() const noexcept { return owns_; }
  bool have_joints() const noexcept { return have_joints_; }
  JointMask out_of_service() const noexcept { return out_of_service_; }
  const RcTaskCounters& counters() const noexcept { return counters_; }
  const kin::JointVector& sent() const noexcept { return sent_; }
  const kin::JointVector& sent_speed() const noexcept { return sent_speed_; }
  const kin::JointVector& references() const noexcept { return references_; }
  kin::JointVector& references() noexcept { return references_; }
  void count_ignored_input() noexcept { ++counters_.ignored_inputs; }
  void count_kinematics_error() noexcept { ++counters_.kinematics_errors; }

 private:
  // true when these are the first joints the handler published.
  bool read_joints() noexcept;
  template <typename Task>
  void take_inputs(Task& task) noexcept {
    RcTaskInput input;
    // Bounded: at most the queue's depth per period.
    for (std::size_t n = 0; n < config::kRcInputQueueDepth && ports_.inputs->try_receive(input); ++n) {
      ++counters_.inputs;
      if (!rc_input_whole(input)) {  // refused: read as it was, an unknown effector moved the right hand
        ++counters_.damaged_inputs;
        continue;
      }
      if (input.kind == RcInputKind::take_ownership) {
        take();
      } else {
        task.on_input(input);
      }
    }
  }
  void take() noexcept;
  // The owner word after this period's releases and retakes; sets owns_ and released_.
  std::uint64_t settle_ownership() noexcept;
  void publish_references(hal::Nanoseconds now, std::uint64_t word, JointMask commanded) noexcept;
  void publish_state(hal::Nanoseconds now, RcTaskState& state) const noexcept;

  RcTaskPorts ports_;
  RcTaskCounters counters_{};
  RobotSample sample_{};
  RobotJointStatus status_{};
  kin::JointVector sent_;        // what the handler sends (samples' position_ref_rad)
  kin::JointVector sent_speed_;  // and its speed (samples' velocity_ref_rad_s)
  kin::JointVector references_;
  JointMask out_of_service_{0};
  RcTaskId id_;
  bool owns_{false};
  bool released_{false};  // this period: lost the motion, the operator's choice no longer standing
  bool have_joints_{false};
  bool chosen_{false};
  bool take_pending_{false};  // the operator gave this task the motion (this process's life), nobody else since
};

}  // namespace rescue::app
