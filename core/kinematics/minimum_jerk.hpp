// Minimum-jerk interpolation (Flash and Hogan): s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 with zero
// velocity and acceleration at both ends, applied to a pose: the position along the straight line,
// the rotation about the fixed axis of R_from^T R_to (geodesic), both with the same s.
#pragma once

#include "core/kinematics/pose.hpp"

namespace rescue::kin {

struct MinimumJerkProfile {
  double s;      // 0..1
  double ds;     // ds/dtau
  double dds;    // d2s/dtau2
};

// tau is clamped to [0, 1].
MinimumJerkProfile minimum_jerk(double tau) noexcept;

// Pose at fraction s (0 -> from, 1 -> to).
Pose interpolate_pose(const Pose& from, const Pose& to, double s) noexcept;

// Twist [v; w] (base_link) of that interpolation when s changes at ds_dt per second.
Vector6 interpolation_twist(const Pose& from, const Pose& to, double ds_dt) noexcept;

}  // namespace rescue::kin
