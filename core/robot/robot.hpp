// The robot, fixed at compile time (design brief section 2): 21 joints on four branches behind a
// two-slave EtherCAT junction. Every task, the master, the simulator and the tests use these tables;
// nothing about the robot's shape is decided anywhere else.
//
// Network, in frame order (EtherCAT slave controllers forward through ports 0, 3, 1, 2):
//
//   master -> junction_a(0) --p3--> junction_b(1) --p1--> right arm (2..8)
//                                                  --p2--> lower body (9..12)
//                           --p1--> torso (13..15)
//                           --p2--> left arm (16..22)
//
// The number in brackets is the auto-increment position. Joints are wired in a line along their
// branch (port 0 in, port 1 out); a link failure at joint X loses X and every joint after it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"

namespace rescue {

constexpr std::size_t kJointCount = 21;
constexpr std::size_t kJunctionCount = 2;
constexpr std::size_t kSlaveCount = kJointCount + kJunctionCount;
constexpr std::size_t kBranchCount = 4;

enum class Branch : std::uint8_t { torso = 0, left_arm = 1, right_arm = 2, lower_body = 3 };

const char* to_string(Branch branch) noexcept;

// CiA 402 modes of operation the joints use (object 0x6060).
enum class ControlMode : std::int8_t {
  none = 0,
  cyclic_position = 8,  // CSP
  cyclic_velocity = 9,  // CSV
  cyclic_torque = 10,   // CST
};

struct JointLimits {
  double position_min_rad;
  double position_max_rad;
  double velocity_max_rad_s;
  double torque_max_nm;
};

// The deceleration a joint's reference may ask for when the joint is brought to rest without the
// task that moved it (the EtherCAT handler's motion intake after an owner's missed deadline or death,
// docs/motion-owner.md): from its velocity limit to rest in kStopFromVelocityLimitS. Below what every
// drive can follow (the simulated drives reach their velocity limit in 0.2 s).
constexpr double kStopFromVelocityLimitS = 0.25;
constexpr double deceleration_limit_rad_s2(const JointLimits& limits) noexcept {
  return limits.velocity_max_rad_s / kStopFromVelocityLimitS;
}

struct JointInfo {
  const char* name;
  Branch branch;
  std::uint8_t order_on_branch;  // 0 = nearest to the switch
  bool continuous;               // tracks: no position limits, position wraps
  ControlMode default_mode;
  double rated_torque_nm;        // CiA 402 torques are in per mille of this (drivers/joint/joint_units.hpp)
  JointLimits limits;
};

// Joint index = position in this table (the design brief's order).
// clang-format off
constexpr std::array<JointInfo, kJointCount> kJoints{{
  //  name                branch               ord  cont   mode                             rated   pos min  pos max  vel   torque
  {"waist_yaw",        Branch::torso,       0, false, ControlMode::cyclic_position, 200.0, {-2.60,  2.60,  1.0, 200.0}},
  {"neck_pan",         Branch::torso,       1, false, ControlMode::cyclic_position,  10.0, {-1.50,  1.50,  2.0,  10.0}},
  {"neck_tilt",        Branch::torso,       2, false, ControlMode::cyclic_position,  10.0, {-0.80,  1.00,  2.0,  10.0}},
  {"l_shoulder_pitch", Branch::left_arm,    0, false, ControlMode::cyclic_position, 150.0, {-3.00,  3.00,  1.5, 150.0}},
  {"l_shoulder_roll",  Branch::left_arm,    1, false, ControlMode::cyclic_position, 150.0, {-0.50,  2.80,  1.5, 150.0}},
  {"l_shoulder_yaw",   Branch::left_arm,    2, false, ControlMode::cyclic_position,  80.0, {-2.80,  2.80,  2.0,  80.0}},
  {"l_elbow",          Branch::left_arm,    3, false, ControlMode::cyclic_position,  80.0, { 0.00,  2.50,  2.0,  80.0}},
  {"l_wrist_yaw",      Branch::left_arm,    4, false, ControlMode::cyclic_position,  20.0, {-2.80,  2.80,  3.0,  20.0}},
  {"l_wrist_pitch",    Branch::left_arm,    5, false, ControlMode::cyclic_position,  20.0, {-1.60,  1.60,  3.0,  20.0}},
  {"l_hand",           Branch::left_arm,    6, false, ControlMode::cyclic_position,  40.0, { 0.00,  1.50,  1.0,  40.0}},
  {"r_shoulder_pitch", Branch::right_arm,   0, false, ControlMode::cyclic_position, 150.0, {-3.00,  3.00,  1.5, 150.0}},
  {"r_shoulder_roll",  Branch::right_arm,   1, false, ControlMode::cyclic_position, 150.0, {-2.80,  0.50,  1.5, 150.0}},
  {"r_shoulder_yaw",   Branch::right_arm,   2, false, ControlMode::cyclic_position,  80.0, {-2.80,  2.80,  2.0,  80.0}},
  {"r_elbow",          Branch::right_arm,   3, false, ControlMode::cyclic_position,  80.0, { 0.00,  2.50,  2.0,  80.0}},
  {"r_wrist_yaw",      Branch::right_arm,   4, false, ControlMode::cyclic_position,  20.0, {-2.80,  2.80,  3.0,  20.0}},
  {"r_wrist_pitch",    Branch::right_arm,   5, false, ControlMode::cyclic_position,  20.0, {-1.60,  1.60,  3.0,  20.0}},
  {"r_hand",           Branch::right_arm,   6, false, ControlMode::cyclic_position,  15.0, { 0.00,  1.20,  2.0,  15.0}},
  {"l_leg",            Branch::lower_body,  0, false, ControlMode::cyclic_position, 300.0, {-0.30,  2.00,  0.8, 300.0}},
  {"r_leg",            Branch::lower_body,  1, false, ControlMode::cyclic_position, 300.0, {-0.30,  2.00,  0.8, 300.0}},
  {"l_track",          Branch::lower_body,  2, true,  ControlMode::cyclic_velocity, 250.0, { 0.00,  0.00, 12.0, 250.0}},
  {"r_track",          Branch::lower_body,  3, true,  ControlMode::cyclic_velocity, 250.0, { 0.00,  0.00, 12.0, 250.0}},
}};
// clang-format on

enum class SlaveKind : std::uint8_t { junction, joint_drive };

constexpr std::uint8_t kNoJoint = 0xFF;
constexpr std::uint8_t kMasterUpstream = 0xFF;

struct SlaveInfo {
  const char* name;
  SlaveKind kind;
  std::uint8_t joint;            // index into kJoints, kNoJoint for junctions
  std::uint8_t upstream;         // position of the slave this one hangs off, kMasterUpstream for the first
  std::uint8_t upstream_port;    // port of the upstream slave it is cabled to
  std::uint16_t station_address; // configured station address the master assigns (0x1000 + position)
};

constexpr std::uint16_t kStationAddressBase = 0x1000;

// Slaves by auto-increment position (frame order).
// clang-format off
constexpr std::array<SlaveInfo, kSlaveCount> kSlaves{{
  {"junction_a",       SlaveKind::junction,    kNoJoint, kMasterUpstream, 0, 0x1000},
  {"junction_b",       SlaveKind::junction,    kNoJoint, 0,  3, 0x1001},
  {"r_shoulder_pitch", SlaveKind::joint_drive, 10,       1,  1, 0x1002},
  {"r_shoulder_roll",  SlaveKind::joint_drive, 11,       2,  1, 0x1003},
  {"r_shoulder_yaw",   SlaveKind::joint_drive, 12,       3,  1, 0x1004},
  {"r_elbow",          SlaveKind::joint_drive, 13,       4,  1, 0x1005},
  {"r_wrist_yaw",      SlaveKind::joint_drive, 14,       5,  1, 0x1006},
  {"r_wrist_pitch",    SlaveKind::joint_drive, 15,       6,  1, 0x1007},
  {"r_hand",           SlaveKind::joint_drive, 16,       7,  1, 0x1008},
  {"l_leg",            SlaveKind::joint_drive, 17,       1,  2, 0x1009},
  {"r_leg",            SlaveKind::joint_drive, 18,       9,  1, 0x100A},
  {"l_track",          SlaveKind::joint_drive, 19,       10, 1, 0x100B},
  {"r_track",          SlaveKind::joint_drive, 20,       11, 1, 0x100C},
  {"waist_yaw",        SlaveKind::joint_drive, 0,        0,  1, 0x100D},
  {"neck_pan",         SlaveKind::joint_drive, 1,        13, 1, 0x100E},
  {"neck_tilt",        SlaveKind::joint_drive, 2,        14, 1, 0x100F},
  {"l_shoulder_pitch", SlaveKind::joint_drive, 3,        0,  2, 0x1010},
  {"l_shoulder_roll",  SlaveKind::joint_drive, 4,        16, 1, 0x1011},
  {"l_shoulder_yaw",   SlaveKind::joint_drive, 5,        17, 1, 0x1012},
  {"l_elbow",          SlaveKind::joint_drive, 6,        18, 1, 0x1013},
  {"l_wrist_yaw",      SlaveKind::joint_drive, 7,        19, 1, 0x1014},
  {"l_wrist_pitch",    SlaveKind::joint_drive, 8,        20, 1, 0x1015},
  {"l_hand",           SlaveKind::joint_drive, 9,        21, 1, 0x1016},
}};
// clang-format on

// A set of joints as a bit mask (bit i = joint i).
using JointMask = std::uint32_t;
constexpr JointMask kAllJoints = (JointMask{1} << kJointCount) - 1;
constexpr JointMask joint_bit(std::size_t joint) noexcept { return JointMask{1} << joint; }

// Auto-increment position of a joint's slave.
constexpr std::size_t slave_position_of_joint(std::size_t joint) noexcept {
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (kSlaves[p].joint == joint) return p;
  }
  return kSlaveCount;
}

// Joints lost when the link into `joint` fails: it and every joint after it on its branch.
constexpr JointMask joints_lost_by_link_failure_at(std::size_t joint) noexcept {
  JointMask lost = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (kJoints[j].branch == kJoints[joint].branch && kJoints[j].order_on_branch >= kJoints[joint].order_on_branch) {
      lost |= joint_bit(j);
    }
  }
  return lost;
}

// All joints of a branch.
constexpr JointMask joints_of_branch(Branch branch) noexcept {
  JointMask mask = 0;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (kJoints[j].branch == branch) mask |= joint_bit(j);
  }
  return mask;
}

// The names of the joints in `mask`, comma-separated ("none" for an empty mask), into `out`
// (truncated to fit, always NUL-terminated when capacity > 0).
void format_joint_names(JointMask mask, char* out, std::size_t capacity) noexcept;
// Room for every joint's name, commas and the terminator.
constexpr std::size_t kJointNamesCapacity = 320;

// Index of the joint called `name`, or kJointCount when there is none.
std::size_t joint_index_by_name(const char* name) noexcept;
// No joint's name is longer (checked below).
constexpr std::size_t kMaxJointNameLength = 31;

// The joints of a comma-separated list of names ("l_elbow,l_hand"), e.g. from the command line.
// Errors: an empty list or item, or an unknown name (detail0: the item's 1-based number).
Result<JointMask> parse_joint_names(const char* list) noexcept;

// Compile-time checks that the tables agree with each other.
namespace robot_checks {
constexpr bool slaves_match_joints() {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const std::size_t p = slave_position_of_joint(j);
    if (p >= kSlaveCount) return false;
    // Names agree, character by character.
    const char* a = kJoints[j].name;
    const char* b = kSlaves[p].name;
    while (*a != '\0' && *a == *b) { ++a; ++b; }
    if (*a != *b) return false;
  }
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (kSlaves[p].station_address != kStationAddressBase + p) return false;
    if (p > 0 && kSlaves[p].upstream >= p) return false;  // upstream comes earlier in frame order
  }
  return true;
}
static_assert(slaves_match_joints(), "kSlaves and kJoints disagree");
static_assert(kJointCount <= 32, "JointMask holds 32 joints");
constexpr bool joint_names_fit() {
  for (std::size_t j = 0; j < kJointCount; ++j) {
    std::size_t length = 0;
    while (kJoints[j].name[length] != '\0') ++length;
    if (length > kMaxJointNameLength) return false;
  }
  return true;
}
static_assert(joint_names_fit(), "a joint name is longer than kMaxJointNameLength");
}  // namespace robot_checks

}  // namespace rescue
