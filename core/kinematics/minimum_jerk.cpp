#include "core/kinematics/minimum_jerk.hpp"

#include <algorithm>

namespace rescue::kin {

MinimumJerkProfile minimum_jerk(double tau) noexcept {
  const double t = std::clamp(tau, 0.0, 1.0);
  const double t2 = t * t;
  const double t3 = t2 * t;
  return MinimumJerkProfile{t3 * (10.0 - 15.0 * t + 6.0 * t2), 30.0 * t2 * (1.0 - 2.0 * t + t2),
                            60.0 * t * (1.0 - 3.0 * t + 2.0 * t2)};
}

Pose interpolate_pose(const Pose& from, const Pose& to, double s) noexcept {
  Pose pose;
  pose.p = from.p + s * (to.p - from.p);
  pose.R = from.R * rotation_exp(s * rotation_log(from.R.transpose() * to.R));
  return pose;
}

Vector6 interpolation_twist(const Pose& from, const Pose& to, double ds_dt) noexcept {
  Vector6 twist;
  twist.head<3>() = ds_dt * (to.p - from.p);
  // R(s) = R0 exp(s w), w = log(R0^T R1): the angular velocity is R(s) w ds/dt = R0 w ds/dt.
  twist.tail<3>() = ds_dt * (from.R * rotation_log(from.R.transpose() * to.R));
  return twist;
}

}  // namespace rescue::kin
