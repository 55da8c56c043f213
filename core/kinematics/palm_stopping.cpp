#include "core/kinematics/palm_stopping.hpp"

#include <cmath>
#include <limits>

namespace rescue::kin {

double palm_braking_deceleration(const IkJacobian6& jacobian, const Vector3& u, JointMask braking) noexcept {
  double deceleration = 0.0;
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
    const std::size_t j = kIkJoints[c];
    if ((braking & joint_bit(j)) == 0) continue;
    deceleration += kJointAcceleration[j] * std::fabs(jacobian.block<3, 1>(0, static_cast<Eigen::Index>(c)).dot(u));
  }
  return deceleration;
}

double least_palm_stopping_travel(const IkJacobian6& jacobian, const Vector3& palm_velocity,
                                  JointMask braking) noexcept {
  const double speed = palm_velocity.norm();
  if (speed < 1e-9) return 0.0;
  const double deceleration = palm_braking_deceleration(jacobian, palm_velocity / speed, braking);
  if (deceleration <= 0.0) return std::numeric_limits<double>::infinity();
  return speed * speed / (2.0 * deceleration);
}

}  // namespace rescue::kin
