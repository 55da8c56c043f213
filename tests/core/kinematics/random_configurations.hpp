// Test support: reproducible random joint values within the joints' position limits.
#pragma once

#include <random>

#include "core/kinematics/kinematic_model.hpp"

namespace rescue::kin::test {

inline double random_angle(std::mt19937_64& rng, std::size_t joint, double shrink = 0.0) {
  const JointLimits& lim = kJoints[joint].limits;
  if (kJoints[joint].continuous) return std::uniform_real_distribution<double>(-10.0, 10.0)(rng);
  const double span = lim.position_max_rad - lim.position_min_rad;
  return std::uniform_real_distribution<double>(lim.position_min_rad + shrink * span,
                                                lim.position_max_rad - shrink * span)(rng);
}

inline JointVector random_configuration(std::mt19937_64& rng, double shrink = 0.0) {
  JointVector q;
  for (std::size_t j = 0; j < kJointCount; ++j) q(static_cast<Eigen::Index>(j)) = random_angle(rng, j, shrink);
  return q;
}

}  // namespace rescue::kin::test
