#include "core/kinematics/rc_period.hpp"

namespace rescue::kin {

RcPeriod::RcPeriod(const JointVector& q_start, const IkSettings& ik, const RescueMotionConfig& motion) noexcept
    : ik_(ik), motion_(q_start, motion), teleop_(q_start, ik.dt_s), planned_(q_start), next_(q_start),
      limiter_(q_start, ik.dt_s), lost_(analyse_lost_capability(q_start, 0)) {}

Result<IkStepReport> RcPeriod::run(double t_s, JointMask out_of_service, const JointVector& teleop_velocity) noexcept {
  if (out_of_service != out_of_service_) {
    out_of_service_ = out_of_service;
    lost_ = analyse_lost_capability(limiter_.position(), out_of_service);
  }
  // Joints out of service are where the references left them.
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const auto row = static_cast<Eigen::Index>(j);
    if ((out_of_service & joint_bit(j)) != 0) planned_(row) = limiter_.position()(row);
  }
  sample_ = motion_.sample(t_s);
  const IkTargets targets{sample_.left, sample_.right, sample_.payload_kg, sample_.left_twist, sample_.right_twist};
  Result<IkStepReport> report = ik_.step(planned_, targets, out_of_service, next_);
  if (report.ok()) planned_ = next_;
  (void)limiter_.step(planned_, out_of_service);
  const Status teleop_status = teleop_.step(teleop_velocity, out_of_service);
  if (!teleop_status.ok()) return teleop_status.error();
  return report;
}

}  // namespace rescue::kin
