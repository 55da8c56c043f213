// Both RC tasks and the EtherCAT handler's motion intake over one TaskLinks, in virtual time, one
// period of each per millisecond: the rig plays the handler (it publishes as joint samples the
// references the intake chose and their speeds, as the handler does) and the joint manager (every joint Enabled in
// its default mode, status published). Tests stop a task's periods to make it "die".
#pragma once

#include <array>
#include <memory>

#include "core/app/links/task_links.hpp"
#include "core/app/runtime/task_ports.hpp"
#include "core/app/tasks/motion_intake.hpp"
#include "core/app/tasks/rescue_task.hpp"
#include "core/app/tasks/teleop_task.hpp"

namespace rescue::app::testing {

inline RescueTaskSettings short_rescue_settings() {
  RescueTaskSettings s = default_rescue_task_settings();
  s.motion.phase_s = {0.4, 0.4, 0.4};
  return s;
}

struct RcTaskRig {
  std::unique_ptr<TaskLinks> links = std::make_unique<TaskLinks>();
  std::unique_ptr<TaskPorts> ports = std::make_unique<TaskPorts>(*links);  // as `run` wires the tasks
  MotionIntake intake{motion_intake_ports(*links), default_intake_settings()};
  std::unique_ptr<RescueTask> rescue = std::make_unique<RescueTask>(ports->rc_task(RcTaskId::rescue), short_rescue_settings());
  std::unique_ptr<TeleopTask> teleop = std::make_unique<TeleopTask>(ports->rc_task(RcTaskId::teleop), default_teleop_task_settings());
  RobotDemand demand{};
  RobotSample sample{};
  RobotJointStatus status{};
  std::array<double, kJointCount> sent{};
  JointMask unreachable{0};
  hal::Nanoseconds now{hal::kNsPerSec};
  bool rescue_runs{true};
  bool teleop_runs{true};

  RcTaskRig() {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      demand[j].enable = true;
      demand[j].mode = static_cast<std::int8_t>(kJoints[j].default_mode);
      status[j].state = fsm::JointState::enabled;
    }
  }

  JointMask driven() const {
    JointMask mask = 0;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if (kJoints[j].default_mode == ControlMode::cyclic_position) mask |= joint_bit(j);
    }
    return mask & ~unreachable;
  }

  // One millisecond: the handler's published values, the RC tasks' periods, the handler's intake.
  void step() {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      sample[j].reachable = (unreachable & joint_bit(j)) == 0;
      if (!sample[j].reachable) continue;
      sample[j].position_ref_rad = sent[j];
      sample[j].velocity_ref_rad_s = intake.sent_speed(j);
      sample[j].position_rad = sent[j];
    }
    links->samples.write(sample);
    links->joint_status.write(status);
    if (rescue_runs) rescue->period(now);
    if (teleop_runs) teleop->period(now);
    const std::array<double, kJointCount>& refs = intake.period(now, demand, driven());
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((driven() & joint_bit(j)) != 0) sent[j] = refs[j];
    }
    now += hal::kNsPerMs;
  }
  void steps(int n) {
    for (int k = 0; k < n; ++k) step();
  }

  // The link into `joint` is cut: the joints behind it are unreachable and recorded lost.
  void cut_link_at(std::size_t joint) {
    unreachable = joints_lost_by_link_failure_at(joint);
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((unreachable & joint_bit(j)) == 0) continue;
      status[j].state = fsm::JointState::error;
      status[j].lost = true;
      demand[j].enable = false;
    }
  }

  // What the message parser queues for an RC task.
  bool send(RcTaskId task, RcInputKind kind, std::uint8_t effector = 0, std::uint8_t action = 0,
            std::array<double, 6> pose = {}) {
    RcTaskInput input;
    input.kind = kind;
    input.effector = effector;
    input.action = action;
    input.pose = pose;
    return links->rc_inputs[static_cast<std::size_t>(task)].try_push(input);
  }
};

}  // namespace rescue::app::testing
