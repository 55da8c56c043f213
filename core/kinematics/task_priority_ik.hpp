// Task-priority damped least-squares IK, one step per RC period (docs/kinematics.md).
//
//   main task  (12 rows): both palms' poses; the waist is in both arms' columns, so it couples them.
//   sub-tasks   (9 rows): the two forearms level (z of their axis = 0), the COM's ground
//                        projection on the centre of the tracks' support polygon, the waist's
//                        posture and the self-collision clearance (self_collision.hpp), in the
//                        main task's null space:
//   dq = J1# e1 + (J2 N1)# (e2 - J2 J1# e1),   N1 = I - J1# J1,   J# = J^T (J J^T + lambda^2 I)^-1
//
// lambda grows smoothly from a tiny floor to lambda_max as the smallest singular value of J1 (an
// inverse-iteration estimate, warm-started every period) falls below a threshold; the sub-tasks
// fade out as lambda grows (a damped N1 is no exact projector, they would leak into the main task).
// Damped, the palm further from its target is damped more, so where the palms' targets conflict the
// palm on its target holds (IkSettings::max_palm_damping_share). Joints out of
// service are locked: their columns are removed, their positions held. A joint that would cross a
// position limit is locked at the limit and the step solved again (at most three passes). The
// sub-task step is scaled down to what the velocity limits leave over from the main task; if the
// main task alone exceeds them, the whole step is scaled, keeping its direction.
//
// Unreachable targets: each step moves towards the damped least-squares minimum of
// |e|^2 + lambda^2 |dq|^2, so repeated steps settle at the closest reachable pose; the report gives
// the remaining residual every period (never an error: the robot keeps its best pose).
// Errors: invalid_argument for non-finite inputs (the references are then left unchanged).
#pragma once

#include <Eigen/Core>
#include <array>

#include "core/kinematics/forward_kinematics.hpp"
#include "core/kinematics/pose.hpp"
#include "core/kinematics/self_collision.hpp"
#include "core/base/result.hpp"

namespace rescue::kin {

struct IkSettings {
  double dt_s{0.001};                 // the RC period
  double feedback_gain{1.0};          // share of the (clamped) palm pose error corrected per step
  double max_linear_step_m{0.004};    // main-task error used per step (position), m
  double max_angular_step_rad{0.02};  // main-task error used per step (rotation), rad
  double singular_threshold{0.08};    // sigma_min below which damping starts
  double max_damping{0.1};           // lambda at sigma_min = 0
  double floor_damping{1e-5};         // lambda far from singularities (keeps J J^T factorisable)
  double subtask_damping{0.05};       // lambda of the sub-task solve
  // Damped, the palm further from its target (distance d_far, the other d_near: metres plus radians
  // at the clamps' ratio) has its rows damped with lambda^2 times
  // clamp((d_far + floor) / (d_near + floor), 1, max share): a palm on its target holds.
  double palm_residual_floor_m{0.001};
  double max_palm_damping_share{10.0};
  double forearm_gain{0.05};          // share of the forearm level error corrected per step
  double com_gain{0.02};              // share of the COM error corrected per step
  double waist_gain{0.02};            // share of the waist's distance from its centre corrected per step
  double waist_weight{1.0};           // weight of the waist posture row among the sub-tasks (0: off)
  double limit_margin_rad{1e-3};      // joints stop this far inside their position limits
  bool forearm_task{true};
  bool com_task{true};
  // Self-collision clearance: repulsive rows among the sub-tasks for the closest pairs within the
  // activation distance; the report's self_collision.stop when a pair is closer than the stop distance.
  bool self_collision_task{true};
  ClearanceSettings clearance{};
};

struct IkTargets {
  Pose left;
  Pose right;
  double payload_kg{0.0};
  // A palm out of the main task (its arm damaged, kin::TaskShape): its six rows are removed, so no
  // joint moves for it; its residual is still reported. (Beside the payload: no padding before the
  // twists, which Eigen aligns to 16 bytes.)
  std::array<bool, 2> palm_active{{true, true}};
  // The targets' velocities (twists [v; w] in base_link, per second): the feed-forward of a
  // trajectory. The step is twist * dt + feedback_gain * (clamped) pose error.
  Vector6 left_twist{Vector6::Zero()};
  Vector6 right_twist{Vector6::Zero()};
};

struct IkStepReport {
  double position_residual_m[2]{};   // |p_target - p| left, right, at the input configuration
  double rotation_residual_rad[2]{};  // |log(R_target R^T)| left, right
  double forearm_tilt[2]{};           // z of the forearm axes (0 = level)
  Vector3 palm_position[2]{Vector3::Zero(), Vector3::Zero()};  // at the input configuration (base_link)
  Vector3 com{Vector3::Zero()};
  double support_margin_m{0.0};       // COM's distance inside the support polygon (negative: outside)
  double sigma_min{0.0};              // estimate of J1's smallest singular value
  double damping{0.0};                // lambda used
  double velocity_scale{1.0};         // <= 1 when the step was slowed to the velocity limits
  JointMask at_limit{0};              // joints locked at a position limit this step
  int passes{0};                      // solves this step (1 + limit passes)
  SelfCollisionReport self_collision{};  // at the input configuration (with self_collision_task)
};

class TaskPriorityIk {
 public:
  explicit TaskPriorityIk(const IkSettings& settings = IkSettings{}) noexcept;

  // One step from the measured (or last commanded) joints `q`: writes the next references into
  // `q_next` (every joint; joints outside the IK and joints out of service keep their q).
  Result<IkStepReport> step(const JointVector& q, const IkTargets& targets, JointMask out_of_service,
                            JointVector& q_next) noexcept;

  // Steps (at most `max_steps`) until both residuals fall below the tolerances; the report of the
  // last step. For tests and off-line planning, not for the period.
  Result<IkStepReport> solve(JointVector& q, const IkTargets& targets, JointMask out_of_service, int max_steps,
                             double position_tolerance_m, double rotation_tolerance_rad) noexcept;

  const IkSettings& settings() const noexcept { return settings_; }
  // Every link's pose at the last step's input configuration (its forward kinematics).
  const LinkPoses& input_poses() const noexcept { return poses_; }

 private:
  using Matrix12 = Eigen::Matrix<double, 12, 12>;
  using Vector12 = Eigen::Matrix<double, 12, 1>;
  using Jacobian12 = Eigen::Matrix<double, 12, kIkDof>;
  // forearms level (2), COM x y (2), waist posture (1), self-collision clearance (kClearanceRows)
  static constexpr int kSubRows = 5 + kClearanceRows;
  using SubJacobian = Eigen::Matrix<double, kSubRows, kIkDof>;
  using SubVector = Eigen::Matrix<double, kSubRows, 1>;
  using Matrix13 = Eigen::Matrix<double, kIkDof, kIkDof>;

  IkSettings settings_;
  Vector12 singular_vector_;  // warm start of the inverse iteration
  LinkPoses poses_;
};

}  // namespace rescue::kin
