#include "core/kinematics/pose.hpp"

#include <cmath>

namespace rescue::kin {

Vector3 rotation_log(const Matrix3& R) noexcept {
  const Eigen::Quaterniond quaternion(R);
  // q and -q are the same rotation: take w >= 0 so the angle is in [0, pi].
  const double sign = quaternion.w() < 0.0 ? -1.0 : 1.0;
  const Vector3 v = sign * quaternion.vec();
  const double s = v.norm();
  const double w = sign * quaternion.w();
  if (s < 1e-12) return 2.0 * v;  // angle ~ 2 s: first order
  return (2.0 * std::atan2(s, w) / s) * v;
}

Matrix3 rotation_exp(const Vector3& w) noexcept {
  const double angle = w.norm();
  if (angle < 1e-15) return Matrix3::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

Vector6 pose_error(const Pose& target, const Pose& pose) noexcept {
  Vector6 e;
  e.head<3>() = target.p - pose.p;
  e.tail<3>() = rotation_log(target.R * pose.R.transpose());
  return e;
}

}  // namespace rescue::kin
