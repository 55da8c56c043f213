#include "core/kinematics/rc_period.hpp"

namespace rescue::kin {

RcPeriod::RcPeriod(const JointVector& q_start, const IkSettings& ik, const RescueMotionConfig& motion) noexcept
    : ik_(ik), motion_(q_start, motion), teleop_(q_start, ik.dt_s), references_(q_start), next_(q_start),
      lost_(analyse_lost_capability(q_start, 0)) {}

Result<IkStepReport> RcPeriod::run(double t_s, JointMask out_of_service, const JointVector& teleop_velocity) noexcept {
  if (out_of_service != out_of_service_) {
    out_of_service_ = out_of_service;
    lost_ = analyse_lost_capability(references_, out_of_service);
  }
  sample_ = motion_.sample(t_s);
  const IkTargets targets{sample_.left, sample_.right, sample_.payload_kg};
  Result<IkStepReport> report = ik_.step(references_, targets, out_of_service, next_);
  if (report.ok()) references_ = next_;
  const Status teleop_status = teleop_.step(teleop_velocity, out_of_service);
  if (!teleop_status.ok()) return teleop_status.error();
  return report;
}

}  // namespace rescue::kin
