// A rigid transform as rotation + translation (fixed-size Eigen, no heap), and the pose error the
// IK drives to zero: position difference and the rotation vector (log map) of R_target * R^T.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/kinematics/kinematic_model.hpp"

namespace rescue::kin {

struct Pose {
  Matrix3 R{Matrix3::Identity()};
  Vector3 p{Vector3::Zero()};

  Pose operator*(const Pose& other) const noexcept { return Pose{R * other.R, p + R * other.p}; }
  Vector3 apply(const Vector3& point) const noexcept { return p + R * point; }
};

// Rotation vector w (axis * angle, |w| <= pi) with exp([w]x) = R.
Vector3 rotation_log(const Matrix3& R) noexcept;
// exp([w]x): the rotation of angle |w| about w.
Matrix3 rotation_exp(const Vector3& w) noexcept;

// Error of `pose` towards `target` in base_link: [target.p - pose.p; log(target.R * pose.R^T)].
Vector6 pose_error(const Pose& target, const Pose& pose) noexcept;

}  // namespace rescue::kin
