#include "core/app/tasks/motion_intake.hpp"

#include <algorithm>
#include <cmath>

#include "core/app/config/firmware_config.hpp"

namespace rescue::app {

MotionIntakeSettings default_intake_settings() noexcept {
  MotionIntakeSettings s;
  s.reference_deadline_ns = config::kOwnerReferenceDeadlineNs;
  s.owner_dead_after_ns = config::kOwnerDeadAfterPeriods * config::kRcTaskPeriodNs;
  s.handler_period_ns = config::kEthercatHandlerPeriodNs;
  return s;
}

MotionIntake::MotionIntake(const MotionIntakePorts& ports, const MotionIntakeSettings& settings) noexcept
    : ports_(ports), settings_(settings) {}

bool MotionIntake::take_owner_references(hal::Nanoseconds now, std::uint64_t word, JointMask driven) noexcept {
  const std::uint8_t task = MotionOwner::task_of(word);
  if (!(*ports_.references)[task].read(snapshot_)) {
    ++counters_.incomplete;
    return false;
  }
  if (snapshot_.owner_word != word) {
    ++counters_.foreign;
    return false;
  }
  if (now - snapshot_.completed_ns > settings_.reference_deadline_ns) {
    ++counters_.stale;
    return false;
  }
  const double seconds = static_cast<double>(settings_.handler_period_ns) / static_cast<double>(hal::kNsPerSec);
  const JointMask joints = snapshot_.commanded & driven;
  // The same completed period as the one taken last period (the owner has not completed a new one
  // yet, or died): its joints are still the owner's, but they keep moving towards rest from their
  // velocity (bring_to_rest) rather than stop dead on the old reference.
  const bool repeated = snapshot_.completed_ns == taken_completed_ns_ && word == taken_word_;
  taken_completed_ns_ = snapshot_.completed_ns;
  taken_word_ = word;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) == 0) continue;
    const JointLimits& lim = kJoints[j].limits;
    double target = snapshot_.position_rad[j];
    if (!std::isfinite(target)) continue;  // this joint holds
    driven_by_owner_ |= joint_bit(j);
    if (repeated) continue;
    if (!kJoints[j].continuous) target = std::clamp(target, lim.position_min_rad, lim.position_max_rad);
    const double step = lim.velocity_max_rad_s * seconds;
    const double limited = std::clamp(target, held_[j] - step, held_[j] + step);
    if (limited != snapshot_.position_rad[j]) ++counters_.clamped;
    velocity_[j] = (limited - held_[j]) / seconds;
    held_[j] = limited;
    fresh_ |= joint_bit(j);
  }
  return true;
}

void MotionIntake::bring_to_rest(JointMask driven) noexcept {
  const double seconds = static_cast<double>(settings_.handler_period_ns) / static_cast<double>(hal::kNsPerSec);
  const JointMask resting = driven & ~fresh_;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((resting & joint_bit(j)) == 0 || velocity_[j] == 0.0) continue;
    if (!settings_.ramped_hold) {
      velocity_[j] = 0.0;
      continue;
    }
    const double v = velocity_[j];
    const double dv = deceleration_limit_rad_s2(kJoints[j].limits) * seconds;
    const double next = std::fabs(v) <= dv ? 0.0 : v - std::copysign(dv, v);
    double target = held_[j] + 0.5 * (v + next) * seconds;
    const JointLimits& lim = kJoints[j].limits;
    const bool at_limit = !kJoints[j].continuous && (target <= lim.position_min_rad || target >= lim.position_max_rad);
    if (!kJoints[j].continuous) target = std::clamp(target, lim.position_min_rad, lim.position_max_rad);
    held_[j] = target;
    velocity_[j] = at_limit ? 0.0 : next;
  }
}

const std::array<double, kJointCount>& MotionIntake::period(hal::Nanoseconds now, const RobotDemand& demand,
                                                            JointMask driven) noexcept {
  decide(now, demand, driven);
  bring_to_rest(driven);
  ports_.owner_joints->store(driven_by_owner_, std::memory_order_relaxed);
  return held_;
}

void MotionIntake::decide(hal::Nanoseconds now, const RobotDemand& demand, JointMask driven) noexcept {
  ++counters_.periods;
  // The joint manager stays the authority: a joint it does not drive, or gives a new reference,
  // takes its reference (a drive enabled later starts where the joint manager set it).
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const bool drives = (driven & joint_bit(j)) != 0;
    const double manager = demand[j].position_ref_rad;
    if (!drives || !driven_before_[j] || manager != manager_ref_[j]) {
      held_[j] = manager;
      velocity_[j] = 0.0;
    }
    manager_ref_[j] = manager;
    driven_before_[j] = drives;
  }
  driving_ = kNoOwnerTask;
  driven_by_owner_ = 0;
  fresh_ = 0;
  const std::uint64_t word = ports_.owner->word();
  const std::uint8_t task = MotionOwner::task_of(word);
  if (task >= protocol::kMaxRcTasks) {  // kNoOwnerTask (0xFF) included: nobody owns the motion
    consecutive_misses_ = 0;
    return;
  }
  ++counters_.owned_periods;
  const std::int64_t beat = (*ports_.rc_heartbeat_ns)[task].load(std::memory_order_acquire);
  if (beat == 0 || now - beat > settings_.owner_dead_after_ns) {
    // Dead (or never started): hold this period, and free the motion for another RC task.
    ++counters_.misses;
    ++consecutive_misses_;
    ports_.owner_misses->fetch_add(1, std::memory_order_relaxed);
    if (ports_.owner->release(word)) {
      ++counters_.releases;
      ports_.owner_releases->fetch_add(1, std::memory_order_relaxed);
    }
    return;
  }
  if (!take_owner_references(now, word, driven)) {
    ++counters_.misses;
    ++consecutive_misses_;
    ports_.owner_misses->fetch_add(1, std::memory_order_relaxed);
    return;
  }
  ++counters_.used_periods;
  consecutive_misses_ = 0;
  driving_ = task;
}

}  // namespace rescue::app
