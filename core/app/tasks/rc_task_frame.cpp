#include "core/app/tasks/rc_task_frame.hpp"

#include <cmath>

namespace rescue::app {

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

bool rc_input_whole(const RcTaskInput& input) noexcept {
  constexpr double kPi = 3.14159265358979323846;  // the operator's protocol's bound (protocol_codec.cpp)
  const bool kind = input.kind == RcInputKind::end_effector_target || input.kind == RcInputKind::hand ||
                    input.kind == RcInputKind::take_ownership;
  const bool effector = input.effector <= static_cast<std::uint8_t>(protocol::Effector::right_hand);
  const bool action = input.action <= static_cast<std::uint8_t>(protocol::HandAction::close);
  bool pose = true;
  for (std::size_t i = 0; i < input.pose.size(); ++i) {
    const double bound = i < 3 ? protocol::kMaxReachM : kPi;
    pose = pose && std::isfinite(input.pose[i]) && input.pose[i] >= -bound && input.pose[i] <= bound;
  }
  return kind && effector && action && pose;
}

RcTaskFrame::RcTaskFrame(const RcTaskPorts& ports, RcTaskId id) noexcept
    : ports_(ports),
      sent_(kin::JointVector::Zero()),
      sent_speed_(kin::JointVector::Zero()),
      references_(kin::JointVector::Zero()),
      id_(id) {}

bool RcTaskFrame::read_joints() noexcept {
  if (ports_.samples->version() == 0) return false;  // the handler has published nothing yet
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
  if (have_joints_) return false;
  have_joints_ = true;
  references_ = sent_;
  return true;
}

void RcTaskFrame::take() noexcept {
  (void)ports_.owner->take(static_cast<std::uint8_t>(index()));
  chosen_ = true;
  take_pending_ = true;  // started once the handler has published the joints
}

std::uint64_t RcTaskFrame::settle_ownership() noexcept {
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
  released_ = false;
  if (owns_ && !owning) {
    ++counters_.ownership_lost;
    released_ = !chosen_;
  }
  owns_ = owning;
  if (owns_) ++counters_.owned_periods;
  return word;
}

void RcTaskFrame::publish_references(hal::Nanoseconds now, std::uint64_t word, JointMask commanded) noexcept {
  ReferenceSpace& space = *ports_.references;
  space.begin();
  for (std::size_t j = 0; j < kJointCount; ++j) space.set(j, references_(static_cast<Eigen::Index>(j)));
  space.complete(owns_ ? word : 0, counters_.periods, commanded, now);
}

void RcTaskFrame::publish_state(hal::Nanoseconds now, RcTaskState& state) const noexcept {
  state.owns = owns_;
  state.out_of_service = out_of_service_;
  state.periods = counters_.periods;
  state.kinematics_errors = counters_.kinematics_errors;
  ports_.state->write(state);
  ports_.heartbeat_ns->store(now, std::memory_order_release);
}

}  // namespace rescue::app
