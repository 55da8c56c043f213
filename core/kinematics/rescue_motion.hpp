// The paper's rescue motion as end-effector trajectories: from the ready posture the two palms
//   lowering    go down and forward to the person lying in front of the tracks,
//   forwarding  slide forward under the person,
//   backwarding come back up towards the chest, lifting the person,
// each phase a minimum-jerk segment of both palm poses (orientation kept). The person's weight
// becomes a payload of the centre of mass during backwarding, growing with the same profile as the
// person is lifted off the ground.
#pragma once

#include <array>
#include <cstdint>

#include "core/kinematics/minimum_jerk.hpp"

namespace rescue::kin {

enum class RescuePhase : std::uint8_t { lowering, forwarding, backwarding, done };
const char* to_string(RescuePhase phase) noexcept;

struct RescueMotionConfig {
  double person_kg{70.0};
  std::array<double, 3> phase_s{3.0, 2.5, 3.0};  // lowering, forwarding, backwarding
  // Palm displacement at the end of each phase from the ready posture (base_link, m; y mirrored).
  Vector3 lowered{0.0, 0.0, -0.12};
  Vector3 forwarded{0.08, 0.0, -0.12};
  Vector3 lifted{-0.08, 0.0, 0.05};
};

struct RescueSample {
  Pose left;
  Pose right;
  Vector6 left_twist{Vector6::Zero()};   // the palms' velocities [v; w] (base_link, per second)
  Vector6 right_twist{Vector6::Zero()};
  double payload_kg{0.0};
  RescuePhase phase{RescuePhase::lowering};
};

// The ready posture the motion starts from: arms forward, forearms level, hands at chest height.
JointVector ready_posture() noexcept;

class RescueMotion {
 public:
  // Plans from the palms' poses at `q_start`.
  explicit RescueMotion(const JointVector& q_start, const RescueMotionConfig& config = RescueMotionConfig{}) noexcept;

  // Targets at time t (s) since the start; after the last phase, its end (phase done).
  RescueSample sample(double t_s) const noexcept;
  double duration_s() const noexcept;
  // Distance from `position` to palm `arm`'s planned path (0 left, 1 right): the straight segments
  // through its waypoints, which the minimum-jerk phases follow (whatever their timing).
  double distance_to_path(int arm, const Vector3& position) const noexcept;

 private:
  RescueMotionConfig config_;
  std::array<Pose, 4> left_;   // waypoints: start, lowered, forwarded, lifted
  std::array<Pose, 4> right_;
};

}  // namespace rescue::kin
