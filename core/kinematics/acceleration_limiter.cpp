#include "core/kinematics/acceleration_limiter.hpp"

#include <algorithm>
#include <cmath>

namespace rescue::kin {

namespace {

// One period of a joint's acceleration-limited ramp from (x, v) towards the wanted position: the
// next (x, v); sets `beyond` when the wanted motion was beyond a limit. `braking`: towards rest
// instead (the wanted motion ignored).
struct RampState {
  double x;
  double v;
};
RampState ramp(std::size_t j, RampState state, double gap, double wanted_velocity, double dt_s, double braking,
               bool& beyond) noexcept {
  const JointLimits& lim = kJoints[j].limits;
  const double a_max = kJointAcceleration[j];
  // A braking joint (braking > 0) changes its speed by at most its braking deceleration.
  const double a_step = braking > 0.0 ? std::min(braking, a_max) : a_max;
  const double low = std::max(state.v - a_step * dt_s, -lim.velocity_max_rad_s);
  const double high = std::min(state.v + a_step * dt_s, lim.velocity_max_rad_s);
  double desired = 0.0;
  if (braking <= 0.0) {
    const double closing = std::min(braking_speed(std::fabs(gap), a_max, dt_s), std::fabs(gap) / dt_s);
    desired = wanted_velocity + std::copysign(closing, gap);
  }
  double v = std::clamp(desired, low, high);
  if (braking <= 0.0) {
    // Never past where the wanted motion can still stop (at a_max from its rate): a ramp closing a
    // gap on a motion that then slows would otherwise overshoot it and come back (a reversal the
    // motion never asked for). As far as the acceleration allows (a motion stopping harder than
    // a_max is overshot, at a_max). In exact arithmetic a motion within the limits is never held
    // back by it (the bound is its own rate); the slack absorbs the rounding.
    constexpr double kSlack = 1e-9;  // rad/s
    const double ahead = gap + wanted_velocity * dt_s;  // where the wanted motion is now, from x
    const double stop_up = ahead + stopping_distance(std::max(0.0, wanted_velocity), a_max, dt_s);
    const double stop_down = ahead - stopping_distance(std::max(0.0, -wanted_velocity), a_max, dt_s);
    v = std::min(v, std::max(low, braking_speed(std::max(0.0, stop_up), a_max, dt_s) + kSlack));
    v = std::max(v, std::min(high, -braking_speed(std::max(0.0, -stop_down), a_max, dt_s) - kSlack));
  }
  if (!kJoints[j].continuous) {
    // Braking in time for the position limits. The intervals meet in exact arithmetic (see the
    // header); a rounding's worth apart, the position limit wins.
    const double stop_high = braking_speed(std::max(0.0, lim.position_max_rad - state.x), a_max, dt_s);
    const double stop_low = -braking_speed(std::max(0.0, state.x - lim.position_min_rad), a_max, dt_s);
    v = std::clamp(v, stop_low, stop_high);
  }
  beyond = braking <= 0.0 && v != desired;
  double x = state.x + v * dt_s;
  if (!kJoints[j].continuous) x = std::clamp(x, lim.position_min_rad, lim.position_max_rad);
  return {x, (x - state.x) / dt_s};
}

}  // namespace

AccelerationLimiter::AccelerationLimiter(const JointVector& start, double dt_s, const JointArray& jerk,
                                         const JointArray& braking) noexcept
    : dt_s_(dt_s), braking_(braking), position_(start), velocity_(JointVector::Zero()), last_wanted_(start) {
  filter_of_.fill(-1);
  for (std::size_t j = 0; j < kJointCount && filter_count_ < kMaxJerkJoints; ++j) {
    if (!(jerk[j] > 0.0)) continue;
    JerkFilter& filter = filters_[filter_count_++];
    filter.joint = j;
    filter.window = std::clamp<std::size_t>(jerk_window(kJointAcceleration[j], jerk[j], dt_s), 1, kMaxJerkWindow);
    filter_of_[j] = static_cast<int>(filter_count_ - 1);
    filter.restart(start(static_cast<Eigen::Index>(j)));
  }
}

void AccelerationLimiter::JerkFilter::restart(double position) noexcept {
  ramp_position = position;
  ramp_velocity = 0.0;
  head = 0;
  steady = kMaxJerkWindow;
  for (std::size_t i = 0; i < window; ++i) history[i] = position;
}

void AccelerationLimiter::reset_joint(std::size_t joint, double position) noexcept {
  const auto row = static_cast<Eigen::Index>(joint);
  position_(row) = position;
  last_wanted_(row) = position;
  velocity_(row) = 0.0;
  if (filter_of_[joint] >= 0) filters_[static_cast<std::size_t>(filter_of_[joint])].restart(position);
}

void AccelerationLimiter::plan_from_references() noexcept {
  last_wanted_ = position_;
  for (std::size_t f = 0; f < filter_count_; ++f) {
    last_wanted_(static_cast<Eigen::Index>(filters_[f].joint)) = filters_[f].ramp_position;
  }
}

void AccelerationLimiter::reset(const JointVector& position) noexcept { reset(position, JointVector::Zero()); }

void AccelerationLimiter::reset(const JointVector& position, const JointVector& velocity) noexcept {
  position_ = position;
  last_wanted_ = position;
  velocity_ = velocity;
  limited_ = 0;
  for (std::size_t f = 0; f < filter_count_; ++f) {
    const auto row = static_cast<Eigen::Index>(filters_[f].joint);
    filters_[f].restart(position(row));
    velocity_(row) = 0.0;
  }
}

const JointVector& AccelerationLimiter::step(const JointVector& wanted, JointMask out_of_service,
                                             JointMask braking) noexcept {
  limited_ = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const auto row = static_cast<Eigen::Index>(j);
    JerkFilter* filter = filter_of_[j] < 0 ? nullptr : &filters_[static_cast<std::size_t>(filter_of_[j])];
    if ((out_of_service & joint_bit(j)) != 0) {
      velocity_(row) = 0.0;
      last_wanted_(row) = position_(row);
      if (filter != nullptr) filter->restart(position_(row));
      continue;
    }
    // The ramp's state: the references themselves, or for a jerk-limited joint the moving
    // average's input.
    const RampState state = filter == nullptr ? RampState{position_(row), velocity_(row)}
                                              : RampState{filter->ramp_position, filter->ramp_velocity};
    // The gap left last period and the wanted motion's own rate: following the rate keeps the gap,
    // the closing speed (braking at a_max towards it, at most the whole gap) closes it.
    const bool brakes = (braking & joint_bit(j)) != 0;
    const double gap = last_wanted_(row) - state.x;
    const double wanted_velocity = (wanted(row) - last_wanted_(row)) / dt_s_;
    bool beyond = false;
    const RampState next = ramp(j, state, gap, wanted_velocity, dt_s_, brakes ? braking_[j] : 0.0, beyond);
    // A braking joint's wanted position is where it is: once the task drives it again, it starts
    // from there without a jump.
    last_wanted_(row) = brakes ? next.x : wanted(row);
    if (beyond) limited_ |= joint_bit(j);
    double x = next.x;
    if (filter != nullptr) {
      // A window holding one value N times over gives it back exactly (and costs no sum: the hands
      // are still most of the time); otherwise summed afresh (at most kMaxJerkWindow terms, for a
      // few joints): no rounding drift.
      filter->steady = next.x == filter->ramp_position ? filter->steady + 1 : 0;
      filter->ramp_position = next.x;
      filter->ramp_velocity = next.v;
      filter->history[filter->head] = next.x;
      filter->head = (filter->head + 1) % filter->window;
      if (filter->steady + 1 >= filter->window) {
        x = next.x;
      } else {
        double sum = 0.0;
        for (std::size_t i = 0; i < filter->window; ++i) sum += filter->history[i];
        x = sum / static_cast<double>(filter->window);
      }
    }
    velocity_(row) = (x - position_(row)) / dt_s_;
    position_(row) = x;
  }
  return position_;
}

}  // namespace rescue::kin
