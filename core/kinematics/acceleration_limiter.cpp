#include "core/kinematics/acceleration_limiter.hpp"

#include <algorithm>
#include <cmath>

namespace rescue::kin {

AccelerationLimiter::AccelerationLimiter(const JointVector& start, double dt_s) noexcept
    : dt_s_(dt_s), position_(start), velocity_(JointVector::Zero()), last_wanted_(start) {}

void AccelerationLimiter::reset(const JointVector& position) noexcept {
  position_ = position;
  last_wanted_ = position;
  velocity_.setZero();
  limited_ = 0;
}

const JointVector& AccelerationLimiter::step(const JointVector& wanted, JointMask out_of_service) noexcept {
  limited_ = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const auto row = static_cast<Eigen::Index>(j);
    if ((out_of_service & joint_bit(j)) != 0) {
      velocity_(row) = 0.0;
      last_wanted_(row) = position_(row);
      continue;
    }
    const JointLimits& lim = kJoints[j].limits;
    const double a_max = kJointAcceleration[j];
    // The gap left last period and the wanted motion's own rate: following the rate keeps the gap,
    // the closing speed (braking at a_max towards it, at most the whole gap) closes it.
    const double gap = last_wanted_(row) - position_(row);
    const double wanted_velocity = (wanted(row) - last_wanted_(row)) / dt_s_;
    last_wanted_(row) = wanted(row);
    const double closing = std::min(braking_speed(std::fabs(gap), a_max, dt_s_), std::fabs(gap) / dt_s_);
    const double desired = wanted_velocity + std::copysign(closing, gap);
    double v = std::clamp(desired, velocity_(row) - a_max * dt_s_, velocity_(row) + a_max * dt_s_);
    v = std::clamp(v, -lim.velocity_max_rad_s, lim.velocity_max_rad_s);
    if (v != desired) limited_ |= joint_bit(j);
    double x = position_(row) + v * dt_s_;
    if (!kJoints[j].continuous) x = std::clamp(x, lim.position_min_rad, lim.position_max_rad);
    velocity_(row) = (x - position_(row)) / dt_s_;
    position_(row) = x;
  }
  return position_;
}

}  // namespace rescue::kin
