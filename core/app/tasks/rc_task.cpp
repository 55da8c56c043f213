#include "core/app/tasks/rc_task.hpp"

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

constexpr JointMask position_mode_joints() noexcept {
  JointMask mask = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (kJoints[j].default_mode == ControlMode::cyclic_position) mask |= joint_bit(j);
  }
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

const char* to_string(RcMode mode) noexcept {
  switch (mode) {
    case RcMode::idle: return "idle";
    case RcMode::approach: return "approach";
    case RcMode::rescue_motion: return "rescue motion";
    case RcMode::target: return "target";
    case RcMode::teleop: return "teleop";
  }
  return "unknown";
}

RcTaskSettings default_rc_task_settings(RcTaskId id) noexcept {
  RcTaskSettings s;
  s.id = id;
  s.period_ns = config::kRcTaskPeriodNs;
  return s;
}

RcTask::RcTask(const RcTaskPorts& ports, const RcTaskSettings& settings) noexcept
    : ports_(ports),
      settings_(settings),
      rescue_(kin::ready_posture(), ik_settings(settings.period_ns), settings.motion, config::kDamagedPalmStopBudgetM),
      ik_(ik_settings(settings.period_ns)),
      teleop_(kin::JointVector::Zero(), hal::seconds(settings.period_ns)),
      limiter_(kin::JointVector::Zero(), hal::seconds(settings.period_ns)),
      wanted_(kin::JointVector::Zero()),
      references_(kin::JointVector::Zero()),
      previous_(kin::JointVector::Zero()),
      sent_(kin::JointVector::Zero()),
      sent_speed_(kin::JointVector::Zero()),
      approach_from_(kin::JointVector::Zero()),
      next_(kin::JointVector::Zero()),
      teleop_velocity_(kin::JointVector::Zero()),
      speed_(kin::JointVector::Zero()),
      mode_(settings.id == RcTaskId::teleop ? RcMode::teleop : RcMode::idle) {
  figures_.min_time_scale = 1.0;
}

void RcTask::measure() noexcept {
  const bool driving = owns_ && mode_ != RcMode::idle && mode_ != RcMode::teleop;
  const double dt = hal::seconds(settings_.period_ns);
  JointMask measured = 0;
  // Only the joints it commands: the others' references are whatever the handler sends them.
  const JointMask own = commanded();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const auto row = static_cast<Eigen::Index>(j);
    const double speed = (references_(row) - previous_(row)) / dt;
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
  if (!driving) return;
  const auto waist_row = static_cast<Eigen::Index>(kin::joint_index("waist_yaw"));
  const double waist = references_(waist_row);
  figures_.max_abs_waist_rad = std::max(figures_.max_abs_waist_rad, std::fabs(waist));
  const kin::TaskShape shape = kin::task_shape_for(out_of_service_);
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
      const double left = references_(static_cast<Eigen::Index>(kMirrored[m][0]));
      const double right = references_(static_cast<Eigen::Index>(kMirrored[m][1]));
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
  // After damage: how far the waist and a damaged arm's palm moved since the loss (FK of what is sent).
  kin::LinkPoses poses;
  kin::forward_kinematics(references_, poses);
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

void RcTask::read_joints() noexcept {
  if (ports_.samples->version() == 0) return;  // the handler has published nothing yet
  RobotSample sample{};
  if (ports_.samples->try_read(sample)) sample_ = sample;
  RobotJointStatus status{};
  if (ports_.joint_status->try_read(status)) status_ = status;
  out_of_service_ = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const auto row = static_cast<Eigen::Index>(j);
    sent_(row) = sample_[j].position_ref_rad;
    sent_speed_(row) = sample_[j].velocity_ref_rad_s;
    if (!sample_[j].reachable || status_[j].lost || status_[j].state == fsm::JointState::error) {
      out_of_service_ |= joint_bit(j);
    }
  }
  if (!have_joints_) {
    have_joints_ = true;
    references_ = sent_;
    previous_ = sent_;
    teleop_.take_ownership(sent_, sent_speed_);
    teleop_.release_ownership();
  }
}

void RcTask::on_take(hal::Nanoseconds now) noexcept {
  ++counters_.takes;
  mode_since_ = now;
  references_ = sent_;  // bumpless: continue from what the handler sends, at the speed it sends it
  if (settings_.id == RcTaskId::teleop) {
    teleop_.take_ownership(sent_, sent_speed_);
    return;
  }
  approach_from_ = sent_;
  wanted_ = sent_;
  limiter_.reset(sent_, sent_speed_);
  // Minimum jerk over D peaks at 1.875 D / T in speed and 5.77 D / T^2 in acceleration.
  approach_s_ = settings_.approach_s;
  const kin::JointVector ready = kin::ready_posture();
  for (const std::size_t j : kin::kIkJoints) {
    const double distance = std::fabs(ready(static_cast<Eigen::Index>(j)) - sent_(static_cast<Eigen::Index>(j)));
    approach_s_ = std::max({approach_s_, 1.875 * distance / kJoints[j].limits.velocity_max_rad_s,
                            std::sqrt(5.7735 * distance / kin::kJointAcceleration[j])});
  }
  mode_ = RcMode::approach;
  phase_ = kin::RescuePhase::lowering;
}

void RcTask::start_target(const RcTaskInput& input) noexcept {
  kin::LinkPoses poses;
  kin::forward_kinematics(references_, poses);
  targets_.left = poses[kin::kLeftEe];
  targets_.right = poses[kin::kRightEe];
  targets_.payload_kg = 0.0;
  if (input.effector == static_cast<std::uint8_t>(protocol::Effector::left_hand)) {
    targets_.left = pose_of(input.pose);
  } else {
    targets_.right = pose_of(input.pose);
  }
  wanted_ = references_;
  mode_ = RcMode::target;
}

void RcTask::take_inputs() noexcept {
  RcTaskInput input;
  // Bounded: at most the queue's depth per period.
  for (std::size_t n = 0; n < config::kRcInputQueueDepth && ports_.inputs->try_receive(input); ++n) {
    ++counters_.inputs;
    switch (input.kind) {
      case RcInputKind::take_ownership:
        (void)ports_.owner->take(static_cast<std::uint8_t>(index()));
        chosen_ = true;
        take_pending_ = true;  // started once the handler has published the joints
        break;
      case RcInputKind::end_effector_target:
        if (settings_.id == RcTaskId::rescue && have_joints_) {
          start_target(input);
        } else {
          ++counters_.ignored_inputs;
        }
        break;
      case RcInputKind::hand: {
        if (settings_.id != RcTaskId::teleop) {
          ++counters_.ignored_inputs;
          break;
        }
        const bool left = input.effector == static_cast<std::uint8_t>(protocol::Effector::left_hand);
        const auto row = static_cast<Eigen::Index>(joint_index_by_name(left ? "l_hand" : "r_hand"));
        const bool close = input.action == static_cast<std::uint8_t>(protocol::HandAction::close);
        teleop_velocity_(row) = close ? settings_.hand_speed_rad_s : -settings_.hand_speed_rad_s;
        break;
      }
    }
  }
}

void RcTask::compute(hal::Nanoseconds now) noexcept {
  if (settings_.id == RcTaskId::teleop) {
    if (!teleop_.step(teleop_velocity_, out_of_service_).ok()) ++counters_.kinematics_errors;
    references_ = teleop_.references();
    return;
  }
  switch (mode_) {
    case RcMode::idle:
    case RcMode::teleop:
      references_ = sent_;  // ready to take over from where the joints are
      wanted_ = sent_;
      limiter_.reset(sent_);
      return;
    case RcMode::approach: {
      const double tau = hal::seconds(now - mode_since_) / approach_s_;
      const double s = kin::minimum_jerk(tau).s;
      const kin::JointVector ready = kin::ready_posture();
      for (const std::size_t j : kin::kIkJoints) {
        const auto row = static_cast<Eigen::Index>(j);
        wanted_(row) = (out_of_service_ & joint_bit(j)) != 0 ? sent_(row)
                                                             : approach_from_(row) + s * (ready(row) - approach_from_(row));
      }
      references_ = limiter_.step(wanted_, out_of_service_);
      if (tau >= 1.0) {
        rescue_ = kin::RcPeriod(references_, ik_settings(settings_.period_ns), settings_.motion, config::kDamagedPalmStopBudgetM);
        mode_ = RcMode::rescue_motion;
        mode_since_ = now;
      }
      return;
    }
    case RcMode::rescue_motion: {
      const Result<kin::IkStepReport> report =
          rescue_.run(hal::seconds(now - mode_since_), out_of_service_, kin::JointVector::Zero());
      if (report.ok()) {
        ik_report_ = report.value();
        if (owns_) {
          figures_.min_support_margin_m = figures_.margin_measured
                                              ? std::min(figures_.min_support_margin_m, ik_report_.support_margin_m)
                                              : ik_report_.support_margin_m;
          figures_.margin_measured = true;
        }
      } else {
        ++counters_.kinematics_errors;
      }
      wanted_ = rescue_.rescue_references();
      references_ = limiter_.step(wanted_, out_of_service_);
      phase_ = rescue_.last_sample().phase;
      return;
    }
    case RcMode::target: {
      // The IK steps from its own plan; the limiter turns the plan into references. A damaged arm's
      // palm leaves the task and its healthy joints brake and hold (kin::TaskShape), as in the
      // rescue motion.
      const kin::TaskShape shape = kin::task_shape_for(out_of_service_);
      targets_.palm_active = shape.palm_active;
      const Result<kin::IkStepReport> report = ik_.step(wanted_, targets_, out_of_service_ | shape.held, next_);
      if (report.ok()) {
        ik_report_ = report.value();
        wanted_ = next_;
      } else {
        ++counters_.kinematics_errors;
      }
      references_ = limiter_.step(wanted_, out_of_service_, shape.held);
      return;
    }
  }
}

JointMask RcTask::commanded() const noexcept {
  if (settings_.id == RcTaskId::teleop) return position_mode_joints() & ~out_of_service_;
  if (mode_ == RcMode::idle) return 0;
  return ik_joints() & ~out_of_service_;
}

void RcTask::publish(hal::Nanoseconds now, std::uint64_t word) noexcept {
  ReferenceSpace& space = *ports_.references;
  space.begin();
  for (std::size_t j = 0; j < kJointCount; ++j) space.set(j, references_(static_cast<Eigen::Index>(j)));
  space.complete(owns_ ? word : 0, counters_.periods, commanded(), now);
  if (settings_.id == RcTaskId::rescue) measure();
  previous_ = references_;
}

void RcTask::period(hal::Nanoseconds now) noexcept {
  ++counters_.periods;
  read_joints();
  take_inputs();
  if (take_pending_ && have_joints_) {
    take_pending_ = false;
    on_take(now);
  }
  std::uint64_t word = ports_.owner->word();
  // A word naming this task that this task never took (only a take_ownership input or a retake,
  // both under chosen_, make one) is a killed predecessor process's: the supervisor restarted this
  // one before the handler's intake noticed the death. It frees it, as the intake would have: the
  // joints hold and the operator gives the motion again (this task's fresh heartbeat would keep
  // the dead generation's word alive, and this task would own it without the operator's choice).
  if (MotionOwner::task_of(word) == index() && !chosen_) {
    if (ports_.owner->release(word)) ++counters_.predecessor_releases;
    word = ports_.owner->word();
  }
  const std::uint8_t holder = MotionOwner::task_of(word);
  if (holder != index() && holder != kNoOwnerTask) chosen_ = false;  // the operator gave it to another task
  // Released while this task was silent too long (a stall, not a crash: it is running again): the
  // operator's choice still stands, so it takes the free motion back and goes on with its motion.
  if (holder == kNoOwnerTask && chosen_ && ports_.owner->take_if_free(static_cast<std::uint8_t>(index()), word)) {
    ++counters_.retakes;
  }
  const bool owning = MotionOwner::task_of(word) == index();
  if (owns_ && !owning) {
    ++counters_.ownership_lost;
    if (!chosen_) {
      if (settings_.id == RcTaskId::rescue) mode_ = RcMode::idle;
      teleop_.release_ownership();
    }
  }
  owns_ = owning;
  if (owns_) ++counters_.owned_periods;
  if (have_joints_) {
    compute(now);
    publish(now, word);
  } else {
    ++counters_.no_samples;
  }
  RcTaskState state = figures_;
  state.mode = static_cast<std::uint8_t>(mode_);
  state.phase = static_cast<std::uint8_t>(phase_);
  state.owns = owns_;
  state.out_of_service = out_of_service_;
  state.periods = counters_.periods;
  state.kinematics_errors = counters_.kinematics_errors;
  state.position_residual_m[0] = ik_report_.position_residual_m[0];
  state.position_residual_m[1] = ik_report_.position_residual_m[1];
  state.rotation_residual_rad[0] = ik_report_.rotation_residual_rad[0];
  state.rotation_residual_rad[1] = ik_report_.rotation_residual_rad[1];
  ports_.state->write(state);
  ports_.heartbeat_ns->store(now, std::memory_order_release);
}

}  // namespace rescue::app
