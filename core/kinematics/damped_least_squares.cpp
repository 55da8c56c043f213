#include "core/kinematics/damped_least_squares.hpp"

#include <algorithm>
#include <cmath>

#include "core/kinematics/cholesky.hpp"

namespace rescue::kin {

DlsResult arm_velocity_ik(const Chain& chain, const ArmVector& q, const Vector6& twist, ArmVector& qdot,
                          const DlsSettings& settings) noexcept {
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  ArmJacobian j;
  Pose tip;
  chain_jacobian(chain, q, j, tip);
  const Matrix6 jjt = j * j.transpose();
  const double floor2 = settings.floor_damping * settings.floor_damping;
  SmallCholesky<6> llt;
  (void)llt.compute(jjt + floor2 * Matrix6::Identity());  // positive definite: floor^2 > 0
  // Smallest singular value: three steps of inverse iteration (the RC task warm-starts instead).
  Vector6 v = Vector6::Constant(1.0 / std::sqrt(6.0));
  double inverse_eigen = 1.0;
  for (int i = 0; i < 3; ++i) {
    const Vector6 w = llt.solve(v);
    inverse_eigen = w.norm();
    v = w / inverse_eigen;
  }
  DlsResult result;
  result.sigma_min = std::sqrt(std::max(0.0, 1.0 / inverse_eigen - floor2));
  double lambda2 = floor2;
  if (result.sigma_min < settings.singular_threshold) {
    const double ratio = result.sigma_min / settings.singular_threshold;
    lambda2 += (1.0 - ratio * ratio) * settings.max_damping * settings.max_damping;
    (void)llt.compute(jjt + lambda2 * Matrix6::Identity());
  }
  result.damping = std::sqrt(lambda2);
  qdot = j.transpose() * llt.solve(twist);
  return result;
}

}  // namespace rescue::kin
