// Test/bench support: conversions between KDL's frames and Jacobians and our Eigen types.
#pragma once

#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>

#include "core/kinematics/kinematic_model.hpp"
#include "core/kinematics/pose.hpp"

namespace rescue::kin::test {

inline Pose to_pose(const KDL::Frame& f) {
  Pose pose;
  for (int r = 0; r < 3; ++r) {
    pose.p(r) = f.p(r);
    for (int c = 0; c < 3; ++c) pose.R(r, c) = f.M(r, c);
  }
  return pose;
}

inline ArmJacobian to_eigen(const KDL::Jacobian& j) {
  ArmJacobian out;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < kArmJoints; ++c) out(r, c) = j(static_cast<unsigned>(r), static_cast<unsigned>(c));
  }
  return out;
}

}  // namespace rescue::kin::test
