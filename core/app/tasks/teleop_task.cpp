#include "core/app/tasks/teleop_task.hpp"

#include "core/app/config/firmware_config.hpp"
#include "core/kinematics/rescue_motion.hpp"

namespace rescue::app {
namespace {

constexpr JointMask position_mode_joints() noexcept {
  JointMask mask = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (kJoints[j].default_mode == ControlMode::cyclic_position) mask |= joint_bit(j);
  }
  return mask;
}

}  // namespace

TeleopTaskSettings default_teleop_task_settings() noexcept {
  TeleopTaskSettings s;
  s.period_ns = config::kRcTaskPeriodNs;
  return s;
}

TeleopTask::TeleopTask(const RcTaskPorts& ports, const TeleopTaskSettings& settings) noexcept
    : frame_(ports, RcTaskId::teleop),
      settings_(settings),
      teleop_(kin::JointVector::Zero(), hal::seconds(settings.period_ns)),
      velocity_(kin::JointVector::Zero()) {}

void TeleopTask::on_first_joints() noexcept {
  teleop_.take_ownership(frame_.sent(), frame_.sent_speed());
  teleop_.release_ownership();
}

void TeleopTask::on_input(const RcTaskInput& input) noexcept {
  switch (input.kind) {
    case RcInputKind::end_effector_target: frame_.count_ignored_input(); break;
    case RcInputKind::hand: {
      const bool left = input.effector == static_cast<std::uint8_t>(protocol::Effector::left_hand);
      const auto row = static_cast<Eigen::Index>(joint_index_by_name(left ? "l_hand" : "r_hand"));
      const bool close = input.action == static_cast<std::uint8_t>(protocol::HandAction::close);
      velocity_(row) = close ? settings_.hand_speed_rad_s : -settings_.hand_speed_rad_s;
      break;
    }
    case RcInputKind::take_ownership: break;  // the frame's
  }
}

void TeleopTask::on_take(hal::Nanoseconds /*now*/) noexcept { teleop_.take_ownership(frame_.sent(), frame_.sent_speed()); }

void TeleopTask::compute(hal::Nanoseconds /*now*/) noexcept {
  if (!teleop_.step(velocity_, frame_.out_of_service()).ok()) frame_.count_kinematics_error();
  frame_.references() = teleop_.references();
}

JointMask TeleopTask::commanded() const noexcept { return position_mode_joints() & ~frame_.out_of_service(); }

// It measures nothing: its figures stay at their start (RcTaskState's, the time scale 1).
void TeleopTask::show(RcTaskState& state) noexcept {
  state = RcTaskState{};
  state.min_time_scale = 1.0;
  state.mode = static_cast<std::uint8_t>(RcMode::teleop);
  state.phase = static_cast<std::uint8_t>(kin::RescuePhase::lowering);
}

void TeleopTask::period(hal::Nanoseconds now) noexcept { frame_.period(*this, now); }

}  // namespace rescue::app
