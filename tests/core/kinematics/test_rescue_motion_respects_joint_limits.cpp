// The whole rescue motion (lowering, forwarding, backwarding with the person as payload) run at
// 1 kHz through the RC period: every reference within its position limits, every step within the
// velocity and acceleration limits, the symmetric motion symmetric (the waist stays at 0), the palms on their trajectory, the COM over the tracks; and with a link cut on
// the left arm mid-motion, the lost joints held while the rest carries on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "core/kinematics/rc_period.hpp"

namespace rescue::kin {
namespace {

struct Worst {
  double acceleration_ratio{0.0};  // |change of velocity| / (a_max dt), must stay <= 1
  double max_abs_waist_rad{0.0};
  double symmetry_rad{0.0};        // largest difference of mirrored arm joints (no-fault motion)
  double position_m{0.0};
  double rotation_rad{0.0};
  double min_margin_m{1e9};
  double velocity_ratio{0.0};  // |dq| / (v_max dt), must stay <= 1
  double limit_excess_rad{0.0};
};

Worst run_motion(RcPeriod& rc, JointMask cut_mask, double cut_at_s, JointVector* held = nullptr) {
  Worst worst;
  const JointVector zero = JointVector::Zero();
  JointVector previous = rc.rescue_references();
  JointVector previous_velocity = JointVector::Zero();
  const char* mirrored[6][2] = {{"l_shoulder_pitch", "r_shoulder_pitch"}, {"l_shoulder_roll", "r_shoulder_roll"},
                                {"l_shoulder_yaw", "r_shoulder_yaw"},     {"l_elbow", "r_elbow"},
                                {"l_wrist_yaw", "r_wrist_yaw"},           {"l_wrist_pitch", "r_wrist_pitch"}};
  // Mirrored in the x-z plane: pitch and elbow joints equal, roll and yaw joints opposite.
  const double mirror_sign[6] = {1.0, -1.0, -1.0, 1.0, -1.0, 1.0};
  const int periods = static_cast<int>(rc.motion().duration_s() * 1000.0) + 500;
  for (int k = 0; k < periods; ++k) {
    const double t = k * 0.001;
    const JointMask lost = t >= cut_at_s ? cut_mask : 0;
    if (held != nullptr && lost != 0 && t - 0.001 < cut_at_s) *held = previous;  // the cut's first period
    const Result<IkStepReport> r = rc.run(t, lost, zero);
    EXPECT_TRUE(r.ok());
    if (!r.ok()) return worst;
    const IkStepReport& rep = r.value();
    const JointVector& q = rc.rescue_references();
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const auto row = static_cast<Eigen::Index>(j);
      const JointLimits& lim = kJoints[j].limits;
      if (!kJoints[j].continuous) {
        worst.limit_excess_rad = std::max({worst.limit_excess_rad, q(row) - lim.position_max_rad,
                                           lim.position_min_rad - q(row)});
      }
      worst.velocity_ratio = std::max(worst.velocity_ratio,
                                      std::fabs(q(row) - previous(row)) / (lim.velocity_max_rad_s * 0.001));
      const double velocity = (q(row) - previous(row)) / 0.001;
      if ((lost & joint_bit(j)) == 0) {
        worst.acceleration_ratio = std::max(worst.acceleration_ratio, std::fabs(velocity - previous_velocity(row)) /
                                                                          (kJointAcceleration[j] * 0.001));
      }
      previous_velocity(row) = velocity;
    }
    worst.max_abs_waist_rad = std::max(worst.max_abs_waist_rad, std::fabs(q(static_cast<Eigen::Index>(joint_index("waist_yaw")))));
    for (int m = 0; m < 6; ++m) {
      const double left = q(static_cast<Eigen::Index>(joint_index(mirrored[m][0])));
      const double right = q(static_cast<Eigen::Index>(joint_index(mirrored[m][1])));
      worst.symmetry_rad = std::max(worst.symmetry_rad, std::fabs(left - mirror_sign[m] * right));
    }
    // Once the left arm is cut, only the right palm is held to its trajectory.
    const int first_arm = (lost & joints_of_branch(Branch::left_arm)) != 0 ? 1 : 0;
    for (int arm = first_arm; arm < 2; ++arm) {
      worst.position_m = std::max(worst.position_m, rep.position_residual_m[arm]);
      worst.rotation_rad = std::max(worst.rotation_rad, rep.rotation_residual_rad[arm]);
    }
    worst.min_margin_m = std::min(worst.min_margin_m, rep.support_margin_m);
    previous = q;
  }
  return worst;
}

TEST(RescueMotion, WholeMotionStaysWithinLimitsOnTrajectoryAndBalanced) {
  RcPeriod rc(ready_posture());
  const Worst worst = run_motion(rc, 0, 1e9);
  std::printf("tracking %.2e m %.2e rad, min support margin %.3f m, velocity ratio %.3f, acceleration ratio %.3f, "
              "max |waist| %.2e rad, symmetry error %.2e rad\n",
              worst.position_m, worst.rotation_rad, worst.min_margin_m, worst.velocity_ratio, worst.acceleration_ratio,
              worst.max_abs_waist_rad, worst.symmetry_rad);
  EXPECT_LE(worst.limit_excess_rad, 0.0);
  EXPECT_LE(worst.velocity_ratio, 1.0 + 1e-9);
  EXPECT_LE(worst.acceleration_ratio, 1.0 + 1e-6);
  // The symmetric motion stays symmetric: once the waist swung to -0.388 rad at t = 7.45 s (its
  // speed doubling every 10 ms) and the elbows ended 2.056 vs 1.526 rad.
  EXPECT_LT(worst.max_abs_waist_rad, 0.01);
  EXPECT_LT(worst.symmetry_rad, 0.01);
  EXPECT_LT(worst.position_m, 0.005);
  EXPECT_LT(worst.rotation_rad, 0.02);
  EXPECT_GT(worst.min_margin_m, 0.05);
  EXPECT_EQ(rc.last_sample().phase, RescuePhase::done);
  EXPECT_DOUBLE_EQ(rc.last_sample().payload_kg, 70.0);
}

TEST(RescueMotion, LinkCutOnTheLeftArmMidMotionHoldsLostJointsAndTheRightArmCarriesOn) {
  RcPeriod rc(ready_posture());
  const JointMask cut = joints_lost_by_link_failure_at(joint_index("l_elbow"));
  JointVector held = JointVector::Zero();
  const Worst worst = run_motion(rc, cut, 4.0, &held);
  const JointVector& q = rc.rescue_references();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((cut & joint_bit(j)) != 0) {
      EXPECT_EQ(q(static_cast<Eigen::Index>(j)), held(static_cast<Eigen::Index>(j))) << kJoints[j].name;
    }
  }
  std::printf("with the cut: right palm tracking %.2e m, acceleration ratio %.3f\n", worst.position_m,
              worst.acceleration_ratio);
  EXPECT_LE(worst.limit_excess_rad, 0.0);
  EXPECT_LE(worst.velocity_ratio, 1.0 + 1e-9);
  EXPECT_LE(worst.acceleration_ratio, 1.0 + 1e-6);
  EXPECT_LT(worst.position_m, 0.01) << "right palm keeps tracking";
  EXPECT_GT(rc.lost_capability().arms[0].lost_directions, 0);
  EXPECT_EQ(rc.lost_capability().arms[1].lost_directions, 0);
}

}  // namespace
}  // namespace rescue::kin
