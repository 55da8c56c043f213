// How far a palm travels, at the least, before its arm's held joints stop it (docs/kinematics.md
// "After damage"). When a link of an arm is cut, the joints behind the cut are unpowered and stop
// where they are; the arm's joints before it (and the waist) are held, braking to rest each at its
// declared acceleration limit. Along the palm's direction of motion u they decelerate it at most
//   A_u = sum_j a_j |J_j . u|      (J_j: the palm's linear Jacobian column of joint j)
// so the palm covers at least |v|^2 / (2 A_u) before it is at rest (first order: the Jacobian where
// the stop starts). The rescue task limits the palm's speed with this bound (RcPeriod), and the
// damage test compares the measured stops with it: one function for both.
#pragma once

#include "core/kinematics/kinematic_model.hpp"

namespace rescue::kin {

// A_u: the palm's largest deceleration along unit `u` from the joints in `braking` (m/s^2).
// `jacobian`: the palm's Jacobian over the IK joints (kin::frame_jacobian).
double palm_braking_deceleration(const IkJacobian6& jacobian, const Vector3& u, JointMask braking) noexcept;

// |v|^2 / (2 A_u) for the palm moving at `palm_velocity` (m/s): 0 at rest, +infinity when the
// joints in `braking` cannot slow it along its direction at all.
double least_palm_stopping_travel(const IkJacobian6& jacobian, const Vector3& palm_velocity,
                                  JointMask braking) noexcept;

}  // namespace rescue::kin
