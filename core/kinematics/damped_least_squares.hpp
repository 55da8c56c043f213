// Damped least-squares velocity IK of one 7-joint arm chain: qdot = J^T (J J^T + lambda^2 I)^-1 v,
// lambda from the same adaptive rule as the task-priority IK (docs/kinematics.md). The single-arm
// kernel measured against KDL's ChainIkSolverVel_wdls by bench rc; the RC period uses
// TaskPriorityIk (both arms, sub-tasks).
#pragma once

#include "core/kinematics/jacobian.hpp"

namespace rescue::kin {

struct DlsSettings {
  double singular_threshold{0.04};
  double max_damping{0.06};
  double floor_damping{1e-5};
};

struct DlsResult {
  double sigma_min{0.0};  // estimate of the Jacobian's smallest singular value
  double damping{0.0};    // lambda used
};

DlsResult arm_velocity_ik(const Chain& chain, const ArmVector& q, const Vector6& twist, ArmVector& qdot,
                          const DlsSettings& settings = DlsSettings{}) noexcept;

}  // namespace rescue::kin
