// The robot's kinematic model as the kinematics code uses it: the generated description
// (core/robot/robot_description.hpp, from core/robot/rescue_robot.urdf) tied to core/robot/robot.hpp's
// joint table, the two arm chains, the joints the RC task's IK moves, and the fixed-size Eigen types.
// Everything here is constexpr or a type; the compile-time checks below make the URDF and kJoints
// one source of truth (names and limits must agree or the firmware does not build).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>

#include "core/robot/robot.hpp"
#include "core/robot/robot_description.hpp"

namespace rescue::kin {

namespace desc = robot_description;
constexpr std::size_t kLinkCount = desc::kLinkCount;
constexpr std::size_t kNoIndex = static_cast<std::size_t>(-1);

using JointVector = Eigen::Matrix<double, static_cast<int>(kJointCount), 1>;  // all 21 joints, kJoints order
using Vector3 = Eigen::Vector3d;
using Matrix3 = Eigen::Matrix3d;
using Vector6 = Eigen::Matrix<double, 6, 1>;

constexpr bool same_name(const char* a, const char* b) {
  while (*a != '\0' && *a == *b) {
    ++a;
    ++b;
  }
  return *a == *b;
}

constexpr std::size_t link_index(const char* name) {
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    if (same_name(desc::kLinks[i].name, name)) return i;
  }
  return kNoIndex;
}

constexpr std::size_t joint_index(const char* name) {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (same_name(kJoints[j].name, name)) return j;
  }
  return kNoIndex;
}

// kJoints index of the joint moving each link (kNoIndex for base_link and fixed frames).
constexpr std::array<std::size_t, kLinkCount> make_link_joints() {
  std::array<std::size_t, kLinkCount> joints{};
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    joints[i] = desc::kLinks[i].type == desc::JointType::fixed ? kNoIndex : joint_index(desc::kLinks[i].joint);
  }
  return joints;
}
constexpr std::array<std::size_t, kLinkCount> kLinkJoint = make_link_joints();

// Acceleration limit of each joint (kJoints order), rad/s^2: the URDF's <limit acceleration>, which
// only the model has (core/robot/robot.hpp's kJoints has no acceleration). Every RC task's
// references respect it (docs/kinematics.md).
constexpr std::array<double, kJointCount> make_joint_accelerations() {
  std::array<double, kJointCount> accelerations{};
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    if (kLinkJoint[i] != kNoIndex) accelerations[kLinkJoint[i]] = desc::kLinks[i].acceleration;
  }
  return accelerations;
}
constexpr std::array<double, kJointCount> kJointAcceleration = make_joint_accelerations();

// Jerk limit of each joint (kJoints order), rad/s^3, 0 where the drive declares none: the URDF's
// optional <limit jerk>. The acceleration limiter keeps the references of a joint that has one within it.
using JointArray = std::array<double, kJointCount>;
constexpr JointArray make_joint_jerks() {
  JointArray jerks{};
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    if (kLinkJoint[i] != kNoIndex) jerks[kLinkJoint[i]] = desc::kLinks[i].jerk;
  }
  return jerks;
}
constexpr JointArray kJointJerk = make_joint_jerks();

// ---- one source of truth: the URDF's joints are kJoints, with the same limits ----
namespace model_checks {
constexpr bool urdf_joints_are_kjoints() {
  std::size_t moving = 0;
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    const desc::Link& link = desc::kLinks[i];
    if (i > 0 && static_cast<std::size_t>(link.parent) >= i) return false;  // parents first
    if (link.type == desc::JointType::fixed) continue;
    ++moving;
    const std::size_t j = kLinkJoint[i];
    if (j == kNoIndex) return false;
    const JointInfo& info = kJoints[j];
    if (info.continuous != (link.type == desc::JointType::continuous)) return false;
    if (link.velocity != info.limits.velocity_max_rad_s || link.effort != info.limits.torque_max_nm) return false;
    if (!(link.acceleration > 0.0)) return false;
    if (!(link.jerk >= 0.0)) return false;  // 0: no jerk limit
    if (!info.continuous &&
        (link.lower != info.limits.position_min_rad || link.upper != info.limits.position_max_rad)) {
      return false;
    }
  }
  return moving == kJointCount;
}
static_assert(urdf_joints_are_kjoints(),
              "core/robot/rescue_robot.urdf and core/robot/robot.hpp kJoints disagree (names, kinds or limits)");
}  // namespace model_checks

// ---- chains: the links from the root to a frame, root excluded ----
constexpr std::size_t kMaxChainLinks = 12;
struct Chain {
  std::array<std::size_t, kMaxChainLinks> links{};  // base side first
  std::size_t size{0};
  std::size_t joints{0};                            // moving links in the chain
};

constexpr Chain make_chain(const char* tip) {
  Chain chain{};
  std::array<std::size_t, kMaxChainLinks> reversed{};
  std::size_t i = link_index(tip);
  while (i != 0 && i != kNoIndex && chain.size < kMaxChainLinks) {
    reversed[chain.size++] = i;
    i = static_cast<std::size_t>(desc::kLinks[i].parent);
  }
  for (std::size_t k = 0; k < chain.size; ++k) {
    chain.links[k] = reversed[chain.size - 1 - k];
    if (kLinkJoint[chain.links[k]] != kNoIndex) ++chain.joints;
  }
  return chain;
}

// The 7-joint arm chains: waist_yaw, shoulder pitch/roll/yaw, elbow, wrist yaw/pitch, to the palm.
constexpr Chain kLeftArm = make_chain("l_ee");
constexpr Chain kRightArm = make_chain("r_ee");
constexpr int kArmJoints = 7;
static_assert(kLeftArm.joints == kArmJoints && kRightArm.joints == kArmJoints, "an arm chain is not 7 joints");
using ArmVector = Eigen::Matrix<double, kArmJoints, 1>;
using ArmJacobian = Eigen::Matrix<double, 6, kArmJoints>;

// The frames the RC task controls.
constexpr std::size_t kLeftEe = link_index("l_ee");
constexpr std::size_t kRightEe = link_index("r_ee");
constexpr std::size_t kLeftForearm = link_index("l_forearm_link");
constexpr std::size_t kRightForearm = link_index("r_forearm_link");
static_assert(kLeftEe != kNoIndex && kRightEe != kNoIndex && kLeftForearm != kNoIndex && kRightForearm != kNoIndex);

// ---- the joints the RC task's IK moves: waist + two 6-joint arms (hands, neck, legs held) ----
constexpr int kIkDof = 13;
constexpr std::array<std::size_t, kIkDof> kIkJoints{
    joint_index("waist_yaw"),
    joint_index("l_shoulder_pitch"), joint_index("l_shoulder_roll"), joint_index("l_shoulder_yaw"),
    joint_index("l_elbow"),          joint_index("l_wrist_yaw"),     joint_index("l_wrist_pitch"),
    joint_index("r_shoulder_pitch"), joint_index("r_shoulder_roll"), joint_index("r_shoulder_yaw"),
    joint_index("r_elbow"),          joint_index("r_wrist_yaw"),     joint_index("r_wrist_pitch")};
using IkVector = Eigen::Matrix<double, kIkDof, 1>;
using IkJacobian6 = Eigen::Matrix<double, 6, kIkDof>;
using IkJacobian3 = Eigen::Matrix<double, 3, kIkDof>;

// Column in the IK vector of each kJoints index (kNoIndex for joints the IK does not move).
constexpr std::array<std::size_t, kJointCount> make_ik_columns() {
  std::array<std::size_t, kJointCount> columns{};
  for (std::size_t j = 0; j < kJointCount; ++j) columns[j] = kNoIndex;
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) columns[kIkJoints[c]] = c;
  return columns;
}
constexpr std::array<std::size_t, kJointCount> kIkColumn = make_ik_columns();

// Link moved by each IK joint.
constexpr std::array<std::size_t, kIkDof> make_ik_links() {
  std::array<std::size_t, kIkDof> links{};
  for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
    for (std::size_t i = 0; i < kLinkCount; ++i) {
      if (kLinkJoint[i] == kIkJoints[c]) links[c] = i;
    }
  }
  return links;
}
constexpr std::array<std::size_t, kIkDof> kIkLink = make_ik_links();

constexpr double total_robot_mass() {
  double mass = 0.0;
  // std::accumulate is constexpr only from C++20.
  // cppcheck-suppress useStlAlgorithm
  for (const desc::Link& link : desc::kLinks) mass += link.mass;
  return mass;
}
constexpr double kRobotMass = total_robot_mass();

}  // namespace rescue::kin
