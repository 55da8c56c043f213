#include "core/app/tasks/motion_intake.hpp"

#include <algorithm>
#include <cmath>

#include "core/app/config/firmware_config.hpp"
#include "core/app/links/heartbeat.hpp"

namespace rescue::app {

namespace {
// Dead: silent longer than the dead-after time on the wall clock AND for as many of the handler's
// own periods (less the one in which the last beat could have been missed). A host stall that holds
// every task, the handler too, passes the first test but not the second: the owner had no CPU
// either, so its silence is jitter, not death (issue 35: 218 ms with every task held released a
// live rescue task under stress-ng). A dead owner still goes within kOwnerDeadAfterPeriods + 1
// handler periods. A damaged beat (links/heartbeat.hpp: negative, or from the future) has no age:
// the owner is judged by the handler's periods alone, in which the beat did not move.
bool silent_for(hal::Nanoseconds now, std::int64_t beat, std::int64_t handler_periods, const MotionIntakeSettings& s) noexcept {
  const HeartbeatAge judged = heartbeat_age(now, beat);
  if (judged.kind == HeartbeatAge::Kind::whole && judged.age <= s.owner_dead_after_ns) return false;
  if (s.handler_period_ns <= 0) return true;  // no period known: the wall clock alone
  return (handler_periods + 1) * s.handler_period_ns > s.owner_dead_after_ns;
}
}  // namespace
namespace {

// A joint brought to rest without the task that moved it: at the smaller of its deceleration limit
// (core/robot/robot.hpp) and its acceleration limit.
kin::JointArray rest_decelerations() noexcept {
  kin::JointArray braking{};
  for (std::size_t j = 0; j < kJointCount; ++j) {
    braking[j] = std::min(deceleration_limit_rad_s2(kJoints[j].limits), kin::kJointAcceleration[j]);
  }
  return braking;
}

}  // namespace

MotionIntakeSettings default_intake_settings() noexcept {
  MotionIntakeSettings s;
  s.reference_deadline_ns = config::kOwnerReferenceDeadlineNs;
  s.owner_dead_after_ns = config::kOwnerDeadAfterPeriods * config::kRcTaskPeriodNs;
  s.handler_period_ns = config::kEthercatHandlerPeriodNs;
  return s;
}

MotionIntake::MotionIntake(const MotionIntakePorts& ports, const MotionIntakeSettings& settings) noexcept
    : ports_(ports),
      settings_(settings),
      limiter_(kin::JointVector::Zero(), hal::seconds(settings.handler_period_ns), kin::kJointJerk, rest_decelerations()),
      wanted_(kin::JointVector::Zero()) {}

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
  const JointMask joints = snapshot_.commanded & driven;
  // The same completed period as the one taken last period (the owner has not completed a new one
  // yet, or died): its joints are still the owner's, but they keep moving towards rest from their
  // velocity (braking, like every joint the owner does not drive) rather than stop dead.
  const bool repeated = snapshot_.completed_ns == taken_completed_ns_ && word == taken_word_;
  taken_completed_ns_ = snapshot_.completed_ns;
  taken_word_ = word;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) == 0) continue;
    const double target = snapshot_.position_rad[j];
    if (!std::isfinite(target)) continue;  // this joint holds
    driven_by_owner_ |= joint_bit(j);
    if (repeated) continue;
    fresh_ |= joint_bit(j);
    wanted_(static_cast<Eigen::Index>(j)) = target;
  }
  return true;
}

void MotionIntake::limit(JointMask driven) noexcept {
  // The owner's joints follow its references; every other driven joint comes to rest and holds
  // (ramped_hold false: it stops where it is, the behaviour measured against).
  const JointMask resting = driven & ~fresh_;
  if (!settings_.ramped_hold) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if ((resting & joint_bit(j)) != 0) limiter_.reset_joint(j, held_[j]);
    }
  }
  const kin::JointVector& sent = limiter_.step(wanted_, ~driven, resting);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    // A joint the joint manager set this period sends the manager's reference as it is (the
    // handler's own limit check judges it: a faulty demand stops the robot, it is never hidden).
    if ((driven & ~manager_set_ & joint_bit(j)) == 0) continue;
    held_[j] = sent(static_cast<Eigen::Index>(j));
    if ((limiter_.limited() & fresh_ & joint_bit(j)) != 0) ++counters_.clamped;
    if (!settings_.limit_references && (fresh_ & joint_bit(j)) != 0) {
      held_[j] = wanted_(static_cast<Eigen::Index>(j));
      limiter_.reset_joint(j, held_[j]);
    }
  }
  // A braking joint's wanted position is where it comes to rest (the next owner starts from there).
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((resting & joint_bit(j)) != 0) wanted_(static_cast<Eigen::Index>(j)) = held_[j];
  }
}

void MotionIntake::measure(JointMask driven) noexcept {
  const double dt = hal::seconds(settings_.handler_period_ns);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((driven & joint_bit(j)) == 0) {
      history_[j] = 0;
      continue;
    }
    // What was sent: the references themselves (history 0: the joint manager set it this period).
    const double v = history_[j] == 0 ? 0.0 : (held_[j] - previous_sent_[j]) / dt;
    previous_sent_[j] = held_[j];
    const double a = (v - speed_[j]) / dt;
    // Figures need the history they are made of: a speed from one sent period, an acceleration
    // from two, a jerk from three (a joint just set by the joint manager starts at rest).
    sent_.max_speed_rad_s[j] = std::max(sent_.max_speed_rad_s[j], std::fabs(v));
    if (history_[j] >= 1) sent_.max_acceleration_rad_s2[j] = std::max(sent_.max_acceleration_rad_s2[j], std::fabs(a));
    if (history_[j] >= 2) sent_.max_jerk_rad_s3[j] = std::max(sent_.max_jerk_rad_s3[j], std::fabs(a - acceleration_[j]) / dt);
    if (!violation_.active()) {
      const double jerk = (a - acceleration_[j]) / dt;
      JointFault fault{};
      if (std::fabs(v) > kJoints[j].limits.velocity_max_rad_s * (1.0 + 1e-9)) {
        fault = {FaultReason::velocity_reference_limit, std::fabs(v), kJoints[j].limits.velocity_max_rad_s};
      } else if (history_[j] >= 1 && std::fabs(a) > kin::kJointAcceleration[j] * (1.0 + 1e-6)) {
        fault = {FaultReason::acceleration_reference_limit, std::fabs(a), kin::kJointAcceleration[j]};
      } else if (history_[j] >= 2 && kin::kJointJerk[j] > 0.0 && std::fabs(jerk) > kin::kJointJerk[j] * (1.0 + 1e-6) + 1e-3) {
        fault = {FaultReason::jerk_reference_limit, std::fabs(jerk), kin::kJointJerk[j]};
      }
      if (fault.active()) {
        violation_ = fault;
        violating_joint_ = j;
      }
    }
    if (history_[j] < 2) ++history_[j];
    speed_[j] = v;
    acceleration_[j] = a;
  }
}

double MotionIntake::sent_speed(std::size_t joint) const noexcept {
  // No history: not driven, or back from the watchdog (rest_at). Within the speed limit: a rounding
  // above it is not a new fault (one beyond it is measure()'s violation).
  if (history_[joint] == 0) return 0.0;
  const double speed_limit = kJoints[joint].limits.velocity_max_rad_s;
  return std::clamp(speed_[joint], -speed_limit, speed_limit);
}

const std::array<double, kJointCount>& MotionIntake::period(hal::Nanoseconds now, const RobotDemand& demand,
                                                            JointMask driven) noexcept {
  decide(now, demand, driven);
  limit(driven);
  measure(driven);
  ports_.owner_joints->store(driven_by_owner_, std::memory_order_relaxed);
  return held_;
}

void MotionIntake::decide(hal::Nanoseconds now, const RobotDemand& demand, JointMask driven) noexcept {
  ++counters_.periods;
  manager_set_ = 0;
  // The joint manager stays the authority: a joint it does not drive, or gives a new reference,
  // takes its reference at rest (a drive enabled later starts where the joint manager set it).
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const bool drives = (driven & joint_bit(j)) != 0;
    const double manager = demand[j].position_ref_rad;
    if (!drives || !driven_before_[j] || manager != manager_ref_[j]) {
      manager_set_ |= joint_bit(j);
      held_[j] = manager;
      wanted_(static_cast<Eigen::Index>(j)) = manager;
      limiter_.reset_joint(j, manager);
      speed_[j] = 0.0;
      acceleration_[j] = 0.0;
      history_[j] = 0;
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
  if (beat != beat_seen_[task]) {
    beat_seen_[task] = beat;
    periods_beat_unchanged_[task] = 0;
    if (heartbeat_age(now, beat).kind == HeartbeatAge::Kind::damaged) ++counters_.damaged_beats;
  } else {
    ++periods_beat_unchanged_[task];
  }
  if (beat == 0 || silent_for(now, beat, periods_beat_unchanged_[task], settings_)) {
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
