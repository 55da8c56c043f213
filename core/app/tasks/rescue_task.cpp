#include "core/app/tasks/rescue_task.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/app/config/firmware_config.hpp"
#include "core/kinematics/forward_kinematics.hpp"
#include "core/kinematics/minimum_jerk.hpp"
#include "core/kinematics/task_shape.hpp"

namespace rescue::app {
namespace {

kin::IkSettings ik_settings(hal::Nanoseconds period_ns) noexcept {
  kin::IkSettings ik;
  ik.dt_s = hal::seconds(period_ns);
  return ik;
}

constexpr JointMask ik_joints() noexcept {
  JointMask mask = 0;
  // std::accumulate is constexpr only from C++20.
  // cppcheck-suppress useStlAlgorithm
  for (const std::size_t j : kin::kIkJoints) mask |= joint_bit(j);
  return mask;
}

// x, y, z (m), roll, pitch, yaw (rad) in base_link -> Pose (R = Rz(yaw) Ry(pitch) Rx(roll)).
kin::Pose pose_of(const std::array<double, 6>& v) noexcept {
  kin::Pose pose;
  pose.p = kin::Vector3(v[0], v[1], v[2]);
  pose.R = (Eigen::AngleAxisd(v[5], kin::Vector3::UnitZ()) * Eigen::AngleAxisd(v[4], kin::Vector3::UnitY()) *
            Eigen::AngleAxisd(v[3], kin::Vector3::UnitX()))
               .toRotationMatrix();
  return pose;
}

}  // namespace

RescueTaskSettings default_rescue_task_settings() noexcept {
  RescueTaskSettings s;
  s.period_ns = config::kRcTaskPeriodNs;
  return s;
}

RescueTask::RescueTask(const RcTaskPorts& ports, const RescueTaskSettings& settings) noexcept
    : rescue_(kin::ready_posture(), ik_settings(settings.period_ns), settings.motion, config::kDamagedPalmStopBudgetM),
      ik_(ik_settings(settings.period_ns)),
      limiter_(kin::JointVector::Zero(), hal::seconds(settings.period_ns)),
      frame_(ports, RcTaskId::rescue),
      settings_(settings),
      wanted_(kin::JointVector::Zero()),
      previous_(kin::JointVector::Zero()),
      approach_from_(kin::JointVector::Zero()),
      next_(kin::JointVector::Zero()),
      speed_(kin::JointVector::Zero()) {
  figures_.min_time_scale = 1.0;
}

void RescueTask::on_input(const RcTaskInput& input) noexcept {
  switch (input.kind) {
    case RcInputKind::end_effector_target:
      if (frame_.have_joints()) {
        start_target(input);
      } else {
        frame_.count_ignored_input();
      }
      break;
    case RcInputKind::hand: frame_.count_ignored_input(); break;
    case RcInputKind::take_ownership: break;  // the frame's
  }
}

void RescueTask::on_take(hal::Nanoseconds now) noexcept {
  mode_since_ = now;
  const kin::JointVector& sent = frame_.sent();
  approach_from_ = sent;
  wanted_ = sent;
  limiter_.reset(sent, frame_.sent_speed());
  // Minimum jerk over D peaks at 1.875 D / T in speed and 5.77 D / T^2 in acceleration.
  approach_s_ = settings_.approach_s;
  const kin::JointVector ready = kin::ready_posture();
  for (const std::size_t j : kin::kIkJoints) {
    const double distance = std::fabs(ready(static_cast<Eigen::Index>(j)) - sent(static_cast<Eigen::Index>(j)));
    approach_s_ = std::max({approach_s_, 1.875 * distance / kJoints[j].limits.velocity_max_rad_s,
                            std::sqrt(5.7735 * distance / kin::kJointAcceleration[j])});
  }
  mode_ = RcMode::approach;
  phase_ = kin::RescuePhase::lowering;
}

void RescueTask::start_target(const RcTaskInput& input) noexcept {
  kin::LinkPoses poses;
  kin::forward_kinematics(frame_.references(), poses);
  targets_.left = poses[kin::kLeftEe];
  targets_.right = poses[kin::kRightEe];
  targets_.payload_kg = 0.0;
  if (input.effector == static_cast<std::uint8_t>(protocol::Effector::left_hand)) {
    targets_.left = pose_of(input.pose);
  } else {
    targets_.right = pose_of(input.pose);
  }
  wanted_ = frame_.references();
  mode_ = RcMode::target;
}

void RescueTask::compute(hal::Nanoseconds now) noexcept {
  switch (mode_) {
    case RcMode::idle:
    case RcMode::teleop:
      frame_.references() = frame_.sent();  // ready to take over from where the joints are
      wanted_ = frame_.sent();
      limiter_.reset(frame_.sent());
      return;
    case RcMode::approach: approach(now); return;
    case RcMode::rescue_motion: run_rescue_motion(now); return;
    case RcMode::target: move_to_target(); return;
  }
}

void RescueTask::approach(hal::Nanoseconds now) noexcept {
  const JointMask locked = frame_.out_of_service();
  const double tau = hal::seconds(now - mode_since_) / approach_s_;
  const double s = kin::minimum_jerk(tau).s;
  const kin::JointVector ready = kin::ready_posture();
  for (const std::size_t j : kin::kIkJoints) {
    const auto row = static_cast<Eigen::Index>(j);
    wanted_(row) = (locked & joint_bit(j)) != 0 ? frame_.sent()(row)
                                                : approach_from_(row) + s * (ready(row) - approach_from_(row));
  }
  frame_.references() = limiter_.step(wanted_, locked);
  if (tau >= 1.0) {
    rescue_ = kin::RcPeriod(frame_.references(), ik_settings(settings_.period_ns), settings_.motion, config::kDamagedPalmStopBudgetM);
    mode_ = RcMode::rescue_motion;
    mode_since_ = now;
  }
}

void RescueTask::run_rescue_motion(hal::Nanoseconds now) noexcept {
  const Result<kin::IkStepReport> report =
      rescue_.run(hal::seconds(now - mode_since_), frame_.out_of_service(), kin::JointVector::Zero());
  if (report.ok()) {
    ik_report_ = report.value();
    if (frame_.owns()) {
      figures_.min_support_margin_m = figures_.margin_measured
                                          ? std::min(figures_.min_support_margin_m, ik_report_.support_margin_m)
                                          : ik_report_.support_margin_m;
      figures_.margin_measured = true;
    }
  } else {
    frame_.count_kinematics_error();
  }
  wanted_ = rescue_.rescue_references();
  frame_.references() = limiter_.step(wanted_, frame_.out_of_service());
  phase_ = rescue_.last_sample().phase;
}

void RescueTask::move_to_target() noexcept {
  // The IK steps from its own plan; the limiter turns the plan into references. A damaged arm's
  // palm leaves the task and its healthy joints brake and hold (kin::TaskShape), as in the
  // rescue motion.
  const JointMask locked = frame_.out_of_service();
  const kin::TaskShape shape = kin::task_shape_for(locked);
  targets_.palm_active = shape.palm_active;
  const Result<kin::IkStepReport> report = ik_.step(wanted_, targets_, locked | shape.held, next_);
  if (report.ok()) {
    ik_report_ = report.value();
    wanted_ = next_;
  } else {
    frame_.count_kinematics_error();
  }
  frame_.references() = limiter_.step(wanted_, locked, shape.held);
}

JointMask RescueTask::commanded() const noexcept {
  if (mode_ == RcMode::idle) return 0;
  return ik_joints() & ~frame_.out_of_service();
}

void RescueTask::after_publish() noexcept {
  measure();
  previous_ = frame_.references();
}

void RescueTask::show(RcTaskState& state) const noexcept {
  state = figures_;
  state.mode = static_cast<std::uint8_t>(mode_);
  state.phase = static_cast<std::uint8_t>(phase_);
  state.position_residual_m[0] = ik_report_.position_residual_m[0];
  state.position_residual_m[1] = ik_report_.position_residual_m[1];
  state.rotation_residual_rad[0] = ik_report_.rotation_residual_rad[0];
  state.rotation_residual_rad[1] = ik_report_.rotation_residual_rad[1];
}

// Per joint it commands: the largest reference speed and acceleration while it drives.
void RescueTask::measure_speeds(bool driving) noexcept {
  const double dt = hal::seconds(settings_.period_ns);
  const kin::JointVector& sent = frame_.references();
  JointMask measured = 0;
  // Only the joints it commands: the others' references are whatever the handler sends them.
  const JointMask own = commanded();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const auto row = static_cast<Eigen::Index>(j);
    const double speed = (sent(row) - previous_(row)) / dt;
    if (driving && (own & joint_bit(j)) != 0) {
      measured |= joint_bit(j);
      figures_.max_speed_rad_s[j] = std::max(figures_.max_speed_rad_s[j], std::fabs(speed));
      if ((measured_ & joint_bit(j)) != 0) {
        figures_.max_acceleration_rad_s2[j] =
            std::max(figures_.max_acceleration_rad_s2[j], std::fabs(speed - speed_(row)) / dt);
      }
    }
    speed_(row) = speed;
  }
  measured_ = measured;
}

void RescueTask::measure() noexcept {
  const bool driving = frame_.owns() && mode_ != RcMode::idle && mode_ != RcMode::teleop;
  measure_speeds(driving);
  if (!driving) return;
  const kin::JointVector& sent = frame_.references();
  const auto waist_row = static_cast<Eigen::Index>(kin::joint_index("waist_yaw"));
  const double waist = sent(waist_row);
  figures_.max_abs_waist_rad = std::max(figures_.max_abs_waist_rad, std::fabs(waist));
  const kin::TaskShape shape = kin::task_shape_for(frame_.out_of_service());
  const auto damaged = static_cast<std::uint8_t>((shape.palm_active[0] ? 0U : 1U) | (shape.palm_active[1] ? 0U : 2U));
  if (damaged == 0) {
    // Mirrored in base_link's x-z plane: pitch and elbow angles equal, roll and yaw opposite.
    constexpr std::size_t kMirrored[6][2] = {
        {kin::joint_index("l_shoulder_pitch"), kin::joint_index("r_shoulder_pitch")},
        {kin::joint_index("l_shoulder_roll"), kin::joint_index("r_shoulder_roll")},
        {kin::joint_index("l_shoulder_yaw"), kin::joint_index("r_shoulder_yaw")},
        {kin::joint_index("l_elbow"), kin::joint_index("r_elbow")},
        {kin::joint_index("l_wrist_yaw"), kin::joint_index("r_wrist_yaw")},
        {kin::joint_index("l_wrist_pitch"), kin::joint_index("r_wrist_pitch")}};
    constexpr double kSign[6] = {1.0, -1.0, -1.0, 1.0, -1.0, 1.0};
    for (std::size_t m = 0; m < 6; ++m) {
      const double left = sent(static_cast<Eigen::Index>(kMirrored[m][0]));
      const double right = sent(static_cast<Eigen::Index>(kMirrored[m][1]));
      figures_.symmetry_error_rad = std::max(figures_.symmetry_error_rad, std::fabs(left - kSign[m] * right));
    }
    figures_.symmetry_measured = true;
  }
  if (mode_ == RcMode::rescue_motion) {
    for (int arm = 0; arm < 2; ++arm) {
      const auto a = static_cast<std::size_t>(arm);
      if (!shape.palm_active[a]) continue;
      figures_.path_deviation_m[a] = std::max(figures_.path_deviation_m[a], rescue_.path_deviation_m(arm));
      figures_.path_measured[a] = true;
    }
    figures_.min_time_scale = std::min(figures_.min_time_scale, rescue_.time_scale());
    figures_.close_pair_seen = rescue_.close_pair_seen();
    figures_.min_self_clearance_m = rescue_.min_clearance_m();
    if (rescue_.collision_stopped()) {
      figures_.collision_stop = true;
      figures_.collision_pair = static_cast<std::int16_t>(rescue_.collision_stop().closest_pair);
      figures_.collision_distance_m = rescue_.collision_stop().closest_distance_m;
    }
    figures_.clipped_periods = rescue_.clipped_periods();
  }
  if (damaged == 0 && !figures_.loss_seen) return;
  measure_after_loss(waist, damaged);
}

// After damage: how far the waist and a damaged arm's palm moved since the loss (FK of what is sent).
void RescueTask::measure_after_loss(double waist, std::uint8_t damaged) noexcept {
  kin::LinkPoses poses;
  kin::forward_kinematics(frame_.references(), poses);
  const auto newly = static_cast<std::uint8_t>(damaged & ~figures_.damaged_arms);
  if (newly != 0 && !figures_.loss_seen) waist_at_loss_ = waist;
  for (int arm = 0; arm < 2; ++arm) {
    const auto a = static_cast<std::size_t>(arm);
    const kin::Vector3& palm = poses[arm == 0 ? kin::kLeftEe : kin::kRightEe].p;
    if ((newly & (1U << a)) != 0) palm_at_loss_[a] = palm;
    if ((damaged & (1U << a)) != 0) {
      figures_.palm_travel_after_loss_m[a] = std::max(figures_.palm_travel_after_loss_m[a], (palm - palm_at_loss_[a]).norm());
    }
  }
  figures_.loss_seen = true;
  figures_.damaged_arms = static_cast<std::uint8_t>(figures_.damaged_arms | damaged);
  figures_.waist_travel_after_loss_rad = std::max(figures_.waist_travel_after_loss_rad, std::fabs(waist - waist_at_loss_));
}

void RescueTask::period(hal::Nanoseconds now) noexcept { frame_.period(*this, now); }

}  // namespace rescue::app
