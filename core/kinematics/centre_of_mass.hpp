// Centre of mass of the whole robot (every link of the URDF) plus a carried payload, its Jacobian
// over the IK joints, and where it stands over the tracks' support polygon.
// The payload (the person) is held by both hands: half its mass at each palm (l_ee, r_ee).
#pragma once

#include "core/kinematics/forward_kinematics.hpp"

namespace rescue::kin {

struct CentreOfMass {
  Vector3 position{Vector3::Zero()};  // base_link
  double mass{0.0};                   // kg, robot + payload
};

CentreOfMass centre_of_mass(const LinkPoses& poses, double payload_kg) noexcept;

// d(com)/dq over the IK joints: column j = w_j x (S_j - M_j p_j) / M, with M_j and S_j the mass and
// first moment of everything joint j carries (its subtree and the payload share it holds).
void centre_of_mass_jacobian(const LinkPoses& poses, double payload_kg, IkJacobian3& jacobian) noexcept;

// Centre of the support polygon (x, y) in base_link.
Eigen::Vector2d support_centre() noexcept;
// Signed distance (m) of the COM's ground projection to the support polygon's border: positive
// inside, negative outside.
double support_margin(const Vector3& com) noexcept;

}  // namespace rescue::kin
