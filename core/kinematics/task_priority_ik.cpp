#include "core/kinematics/task_priority_ik.hpp"

#include <algorithm>
#include <cmath>

#include "core/kinematics/centre_of_mass.hpp"
#include "core/kinematics/cholesky.hpp"
#include "core/kinematics/jacobian.hpp"

namespace rescue::kin {
namespace {

// Scales a 3-vector down to `limit` (keeps its direction).
template <typename Segment>
void clamp_norm(Segment&& v, double limit) noexcept {
  const double n = v.norm();
  if (n > limit) v *= limit / n;
}

bool finite(const Pose& pose) noexcept { return pose.R.allFinite() && pose.p.allFinite(); }

// Row of d(a_z)/dq for a forearm whose axis is a = R.col(2): (w x a)_z = w_x a_y - w_y a_x.
using IkRow = Eigen::Matrix<double, 1, kIkDof>;
IkRow forearm_level_row(const LinkPoses& poses, std::size_t forearm, double& tilt) noexcept {
  IkRow row;
  const Vector3 a = poses[forearm].R.col(2);
  tilt = a.z();
  for (std::size_t c = 0; c < kIkLink.size(); ++c) {
    const std::size_t link = kIkLink[c];
    const auto col = static_cast<Eigen::Index>(c);
    // The joint's link is the ancestor asked about (not swapped).
    // NOLINTNEXTLINE(readability-suspicious-call-argument)
    if (!is_ancestor_or_self(link, forearm)) {
      row(col) = 0.0;
      continue;
    }
    const Vector3 w = joint_axis(poses[link], link);
    row(col) = w.x() * a.y() - w.y() * a.x();
  }
  return row;
}

// Each main-task row's share of the damping above the floor: the palm further from its target (by
// position + rotation at the clamps' ratio) takes clamp((d_far + floor) / (d_near + floor), 1, max),
// the other palm 1. Where the two palms' targets conflict, the damped steps settle with the clamped
// errors in the ratio of the palms' damping, so the palm on its target holds (docs/kinematics.md).
Eigen::Matrix<double, 12, 1> palm_damping_share(const IkStepReport& report, const IkSettings& s) noexcept {
  const double metre_per_rad = s.max_linear_step_m / s.max_angular_step_rad;
  const double left = report.position_residual_m[0] + metre_per_rad * report.rotation_residual_rad[0];
  const double right = report.position_residual_m[1] + metre_per_rad * report.rotation_residual_rad[1];
  const double far_share = std::clamp((std::max(left, right) + s.palm_residual_floor_m) /
                                          (std::min(left, right) + s.palm_residual_floor_m),
                                      1.0, s.max_palm_damping_share);
  Eigen::Matrix<double, 12, 1> share = Eigen::Matrix<double, 12, 1>::Ones();
  if (left > right) {
    share.head<6>().setConstant(far_share);
  } else {
    share.tail<6>().setConstant(far_share);
  }
  return share;
}

// The main task at `poses`: both palms' frame Jacobians and clamped pose errors (the trajectory's
// motion fed forward), the residuals into `report`. A palm out of the main task (IkTargets::palm_active)
// has its rows and error zero and is marked in `dropped_rows`: its diagonal is 1 in J J^T (a
// decoupled unit row: it neither takes part in the solve nor looks like a singularity).
struct MainTask {
  Eigen::Matrix<double, 12, kIkDof> j1;
  Eigen::Matrix<double, 12, 1> e1;
  Eigen::Matrix<double, 12, 1> damping_share;
  Eigen::Matrix<double, 12, 1> dropped_rows;
};
MainTask build_main_task(const LinkPoses& poses, const IkTargets& targets, const IkSettings& s,
                         IkStepReport& report) noexcept {
  using Vector12 = Eigen::Matrix<double, 12, 1>;
  MainTask m;
  IkJacobian6 jframe;
  frame_jacobian(poses, kLeftEe, jframe);
  m.j1.topRows<6>() = jframe;
  frame_jacobian(poses, kRightEe, jframe);
  m.j1.bottomRows<6>() = jframe;
  m.e1.head<6>() = pose_error(targets.left, poses[kLeftEe]);
  m.e1.tail<6>() = pose_error(targets.right, poses[kRightEe]);
  for (int arm = 0; arm < 2; ++arm) {
    const Eigen::Index at = Eigen::Index{6} * arm;
    report.position_residual_m[arm] = m.e1.segment<3>(at).norm();
    report.rotation_residual_rad[arm] = m.e1.segment<3>(at + 3).norm();
    clamp_norm(m.e1.segment<3>(at), s.max_linear_step_m);
    clamp_norm(m.e1.segment<3>(at + 3), s.max_angular_step_rad);
  }
  const bool both_palms = targets.palm_active[0] && targets.palm_active[1];
  m.damping_share = both_palms ? palm_damping_share(report, s) : Vector12::Ones();
  m.dropped_rows = Vector12::Zero();
  for (int arm = 0; arm < 2; ++arm) {
    if (targets.palm_active[static_cast<std::size_t>(arm)]) continue;
    m.j1.middleRows<6>(Eigen::Index{6} * arm).setZero();
    m.dropped_rows.segment<6>(Eigen::Index{6} * arm).setOnes();
  }
  // The trajectory's own motion is fed forward; the pose error is fed back with feedback_gain.
  m.e1 *= s.feedback_gain;
  m.e1.head<6>() += s.dt_s * targets.left_twist;
  m.e1.tail<6>() += s.dt_s * targets.right_twist;
  m.e1 = m.e1.cwiseProduct(Vector12::Ones() - m.dropped_rows);
  return m;
}

}  // namespace

TaskPriorityIk::TaskPriorityIk(const IkSettings& settings) noexcept
    : settings_(settings), singular_vector_(Vector12::Constant(1.0 / std::sqrt(12.0))) {}

Result<IkStepReport> TaskPriorityIk::step(const JointVector& q, const IkTargets& targets, JointMask out_of_service,
                                          JointVector& q_next) noexcept {
  if (!q.allFinite()) return make_error(Errc::invalid_argument, "joint positions are not finite");
  if (!finite(targets.left) || !finite(targets.right) || !targets.left_twist.allFinite() ||
      !targets.right_twist.allFinite() || !std::isfinite(targets.payload_kg) ||
      targets.payload_kg < 0.0) {
    return make_error(Errc::invalid_argument, "targets are not finite");
  }
  const IkSettings& s = settings_;
  IkStepReport report;
  forward_kinematics(q, poses_);
  report.palm_position[0] = poses_[kLeftEe].p;
  report.palm_position[1] = poses_[kRightEe].p;

  // ---- main task: both palms ----
  const MainTask main_task = build_main_task(poses_, targets, s, report);
  const Jacobian12& j1 = main_task.j1;
  const Vector12& e1 = main_task.e1;
  const Vector12& damping_share = main_task.damping_share;
  const Vector12& dropped_rows = main_task.dropped_rows;

  // ---- sub-tasks: forearms level, COM over the support centre ----
  SubJacobian j2 = SubJacobian::Zero();
  SubVector e2 = SubVector::Zero();
  j2.row(0) = forearm_level_row(poses_, kLeftForearm, report.forearm_tilt[0]);
  j2.row(1) = forearm_level_row(poses_, kRightForearm, report.forearm_tilt[1]);
  if (s.forearm_task) {
    e2(0) = -s.forearm_gain * report.forearm_tilt[0];
    e2(1) = -s.forearm_gain * report.forearm_tilt[1];
  } else {
    j2.topRows<2>().setZero();
  }
  const CentreOfMass com = centre_of_mass(poses_, targets.payload_kg);
  report.com = com.position;
  report.support_margin_m = support_margin(com.position);
  if (s.com_task) {
    IkJacobian3 jcom;
    centre_of_mass_jacobian(poses_, targets.payload_kg, jcom);
    j2.middleRows<2>(2) = jcom.topRows<2>();
    e2.segment<2>(2) = s.com_gain * (support_centre() - com.position.head<2>());
  }
  // Waist posture: the waist back to its centre, weighted. In the main task's one-dimensional
  // null space the forearm rows alone have an asymmetric optimum when the forearms are tilted
  // (turning the waist levels one forearm at the other's cost): without this row a symmetric
  // motion left symmetry with the waist's speed doubling every 10 ms. With it, the symmetric
  // posture is the sub-tasks' optimum and stays stable.
  if (s.waist_weight > 0.0) {
    j2(4, 0) = s.waist_weight;
    e2(4) = -s.waist_weight * s.waist_gain * q(static_cast<Eigen::Index>(kIkJoints[0]));
  }
  // ---- sub-task: self-collision clearance, the last kClearanceRows rows (self_collision.hpp) ----
  if (s.self_collision_task) {
    ClearanceRows rows;
    ClearanceErrors errors;
    report.self_collision = clearance_rows(poses_, s.clearance, rows, errors);
    j2.bottomRows<kClearanceRows>() = rows;
    e2.tail<kClearanceRows>() = errors;
  }

  // ---- locked columns: out of service, then joints held at a position limit ----
  IkVector dq_fixed = IkVector::Zero();
  std::array<bool, kIkDof> locked{};
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) locked[c] = (out_of_service & joint_bit(kIkJoints[c])) != 0;

  IkVector dq = IkVector::Zero();
  const double floor2 = s.floor_damping * s.floor_damping;
  for (int pass = 0; pass < 3; ++pass) {
    report.passes = pass + 1;
    Jacobian12 j1m = j1;
    SubJacobian j2m = j2;
    for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
      if (!locked[c]) continue;
      j1m.col(static_cast<Eigen::Index>(c)).setZero();
      j2m.col(static_cast<Eigen::Index>(c)).setZero();
    }
    const Vector12 e1r = e1 - j1 * dq_fixed;
    // Products of these sizes would go to Eigen's blocked GEMM (a heap fallback and a lock in
    // its reach); lazyProduct keeps them coefficient-based, as a real-time period needs.
    Matrix12 jjt = j1m.lazyProduct(j1m.transpose());
    jjt.diagonal() += dropped_rows;

    // Smallest singular value of J1 by two steps of inverse iteration on J J^T + floor^2 I.
    SmallCholesky<12> llt;
    if (!llt.compute(jjt + floor2 * Matrix12::Identity())) {
      return make_error(Errc::invalid_argument, "main task matrix is not positive definite");
    }
    Vector12 v = singular_vector_;
    double inverse_eigen = 0.0;
    for (int i = 0; i < 2; ++i) {
      const Vector12 w = llt.solve(v);
      inverse_eigen = w.norm();
      v = w / inverse_eigen;
    }
    if (v.allFinite()) singular_vector_ = v;
    const double sigma2 = std::max(0.0, 1.0 / inverse_eigen - floor2);
    report.sigma_min = std::sqrt(sigma2);
    double lambda2 = floor2;
    if (report.sigma_min < s.singular_threshold) {
      const double ratio = report.sigma_min / s.singular_threshold;
      lambda2 += (1.0 - ratio * ratio) * s.max_damping * s.max_damping;
      Matrix12 damped = jjt;
      damped.diagonal() += Vector12::Constant(floor2) + (lambda2 - floor2) * damping_share;
      if (!llt.compute(damped)) {
        return make_error(Errc::invalid_argument, "damped main task matrix is not positive definite");
      }
    }
    report.damping = std::sqrt(lambda2);

    // X = (J J^T + lambda^2 I)^-1 J, so J# = X^T and N1 = I - X^T J.
    const Jacobian12 x = llt.solve_columns(j1m);
    const IkVector dq1 = x.transpose() * e1r;
    const Matrix13 n1 = Matrix13::Identity() - x.transpose().lazyProduct(j1m);
    const SubJacobian j2n = j2m.lazyProduct(n1);
    const SubVector e2r = e2 - j2 * (dq_fixed + dq1);
    SmallCholesky<kSubRows> sub;
    if (!sub.compute(j2n.lazyProduct(j2n.transpose()) +
                     s.subtask_damping * s.subtask_damping * Eigen::Matrix<double, kSubRows, kSubRows>::Identity())) {
      return make_error(Errc::invalid_argument, "sub-task matrix is not positive definite");
    }
    const IkVector dq2 = j2n.transpose() * sub.solve(e2r);
    // The sub-tasks may only use what the velocity limits leave over from the main task.
    const IkVector main = dq_fixed + dq1;
    double sub_scale = 1.0;
    for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
      const auto col = static_cast<Eigen::Index>(c);
      const double reach = kJoints[kIkJoints[c]].limits.velocity_max_rad_s * s.dt_s;
      if (std::fabs(main(col)) >= reach) {
        sub_scale = 0.0;
      } else if (dq2(col) != 0.0) {
        const double room = (dq2(col) > 0.0 ? reach - main(col) : -reach - main(col)) / dq2(col);
        sub_scale = std::min(sub_scale, room);
      }
    }
    // Damping makes N1 an imperfect projector: the sub-tasks fade out as the damping grows, so
    // near a singularity they cannot leak into (and oscillate against) the main task.
    const double fade = 1.0 - (lambda2 - floor2) / (s.max_damping * s.max_damping);
    dq = main + std::max(0.0, sub_scale) * fade * dq2;

    // Position limits: lock the joints that would cross one and solve again.
    bool clamped = false;
    for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
      if (locked[c]) continue;
      const std::size_t j = kIkJoints[c];
      const auto col = static_cast<Eigen::Index>(c);
      const JointLimits& lim = kJoints[j].limits;
      const double qj = q(static_cast<Eigen::Index>(j));
      const double lo = lim.position_min_rad + s.limit_margin_rad;
      const double hi = lim.position_max_rad - s.limit_margin_rad;
      const double next = qj + dq(col);
      if (next <= hi && next >= lo) continue;
      const double bound = next > hi ? hi : lo;
      const double reach = lim.velocity_max_rad_s * s.dt_s;
      dq_fixed(col) = std::clamp(bound - qj, -reach, reach);
      locked[c] = true;
      report.at_limit |= joint_bit(j);
      clamped = true;
    }
    if (!clamped) break;
  }
  // Joints locked in the last pass move only to their limit.
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
    if (locked[c]) dq(static_cast<Eigen::Index>(c)) = dq_fixed(static_cast<Eigen::Index>(c));
  }

  // Velocity limits: one common scale keeps the step's direction.
  double scale = 1.0;
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
    const double reach = kJoints[kIkJoints[c]].limits.velocity_max_rad_s * s.dt_s;
    const double step_rad = std::fabs(dq(static_cast<Eigen::Index>(c)));
    if (step_rad > reach) scale = std::min(scale, reach / step_rad);
  }
  report.velocity_scale = scale;
  dq *= scale;

  q_next = q;
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
    const std::size_t j = kIkJoints[c];
    if ((out_of_service & joint_bit(j)) != 0) continue;
    const auto row = static_cast<Eigen::Index>(j);
    const JointLimits& lim = kJoints[j].limits;
    q_next(row) = std::clamp(q(row) + dq(static_cast<Eigen::Index>(c)), lim.position_min_rad, lim.position_max_rad);
  }
  return report;
}

Result<IkStepReport> TaskPriorityIk::solve(JointVector& q, const IkTargets& targets, JointMask out_of_service,
                                           int max_steps, double position_tolerance_m,
                                           double rotation_tolerance_rad) noexcept {
  IkStepReport report;
  JointVector next = q;
  for (int i = 0; i < max_steps; ++i) {
    Result<IkStepReport> r = step(q, targets, out_of_service, next);
    if (!r.ok()) return r;
    report = r.value();
    if (std::max(report.position_residual_m[0], report.position_residual_m[1]) <= position_tolerance_m &&
        std::max(report.rotation_residual_rad[0], report.rotation_residual_rad[1]) <= rotation_tolerance_rad) {
      return report;
    }
    q = next;
  }
  return report;
}

}  // namespace rescue::kin
