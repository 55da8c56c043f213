// The teleoperation RC task: its references every period, in the RC task frame (rc_task_frame.hpp:
// joints, inputs, ownership, reference space, heartbeat). Joint-space teleoperation
// (kin::JointSpaceTeleop): the hands open or close at a fixed speed (`ctl hand`); taking the motion
// continues from the references being sent and their speeds (with no command a moving joint brakes
// at its acceleration limit), within the joints' velocity and acceleration limits. End-effector
// targets are the rescue task's: counted as ignored. No heap after construction.
#pragma once

#include "core/app/tasks/rc_task_frame.hpp"
#include "core/kinematics/joint_space_teleop.hpp"

namespace rescue::app {

struct TeleopTaskSettings {
  hal::Nanoseconds period_ns{0};  // config::kRcTaskPeriodNs
  double hand_speed_rad_s{0.5};   // hands open / close at this speed
};
TeleopTaskSettings default_teleop_task_settings() noexcept;

class TeleopTask {
 public:
  // Every port must be non-null; they are the teleop task's (RcTaskId::teleop).
  TeleopTask(const RcTaskPorts& ports, const TeleopTaskSettings& settings) noexcept;

  // One period at `now` (the tasks' common monotonic clock).
  // Out of line: the symbol toolchain/rt-verify.json names as this task's period entry.
  void period(hal::Nanoseconds now) noexcept;

  static RcMode mode() noexcept { return RcMode::teleop; }
  bool owns() const noexcept { return frame_.owns(); }
  JointMask out_of_service() const noexcept { return frame_.out_of_service(); }
  const RcTaskCounters& counters() const noexcept { return frame_.counters(); }
  const kin::JointVector& references() const noexcept { return frame_.references(); }

 private:
  friend class RcTaskFrame;  // calls the steps below
  void on_first_joints() noexcept;
  void on_input(const RcTaskInput& input) noexcept;
  void on_take(hal::Nanoseconds now) noexcept;
  void on_released() noexcept { teleop_.release_ownership(); }
  void compute(hal::Nanoseconds now) noexcept;
  JointMask commanded() const noexcept;
  void after_publish() noexcept {}
  static void show(RcTaskState& state) noexcept;

  RcTaskFrame frame_;
  TeleopTaskSettings settings_;
  kin::JointSpaceTeleop teleop_;
  kin::JointVector velocity_;  // the hands' commanded speeds
};

}  // namespace rescue::app
