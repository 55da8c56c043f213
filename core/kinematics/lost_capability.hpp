// What the arms can no longer do when joints are out of service: for each palm, the task-space
// directions (of [x y z rx ry rz] in base_link) that the remaining joints cannot move, from the SVD
// of the palm's Jacobian with the lost joints' columns removed; and the reach lost with the elbow. Computed when the set of joints out
// of service changes (an SVD per arm: too slow for every period, cheap once).
#pragma once

#include <array>
#include <cstdint>

#include "core/kinematics/kinematic_model.hpp"

namespace rescue::kin {

struct ArmCapability {
  int lost_directions{0};                                   // 6 - rank of the reduced Jacobian
  Eigen::Matrix<double, 6, 6> directions{Eigen::Matrix<double, 6, 6>::Zero()};  // first lost_directions columns
  std::uint8_t uncontrollable_axes{0};  // bit i: task axis i (x y z rx ry rz) mostly (> 50 %) in the lost directions
  double sigma_min{0.0};                // smallest singular value of the remaining directions
  // Lost reach: the elbow alone sets the distance from the shoulder yaw joint to the wrist (the
  // upper arm's and the forearm's lengths and the angle between them). With the elbow out of
  // service that distance is fixed at its held value: the palm keeps its six directions at this
  // posture (the Jacobian's rank), but every target needing another distance is out of reach.
  bool reach_fixed{false};
  double wrist_distance_m{0.0};         // shoulder yaw joint to wrist, now (fixed when reach_fixed)
  double wrist_distance_min_m{0.0};     // the healthy arm's range (elbow over its limits)
  double wrist_distance_max_m{0.0};
};

struct LostCapability {
  std::array<ArmCapability, 2> arms{};  // 0 left palm, 1 right palm
};

// Rank threshold: singular values below this (m/rad or rad/rad) count as lost.
constexpr double kLostSingularValue = 1e-6;

LostCapability analyse_lost_capability(const JointVector& q, JointMask out_of_service) noexcept;

// "x,rz" style names of an axis mask into `out` ("none" when empty); always NUL-terminated.
void format_axes(std::uint8_t axes, char* out, std::size_t capacity) noexcept;

}  // namespace rescue::kin
