// Self-collision: distances between the links' collision shapes every RC period, and the rows of
// the IK's clearance sub-task (docs/kinematics.md, "Self-collision avoidance").
//
// The shapes are the URDF's <collision> boxes (generated: desc::kCollisionShapes); a track, which
// its continuous joint turns to any angle faster than any IK joint can get away, is checked as its
// envelope over the whole turn (a cylinder). Distances are exact (GJK on the shapes' support
// points, with the closest points on both), computed only for the pairs a cheap bound cannot rule
// out of the activation distance (bounding spheres, then the boxes' face axes). No heap, fixed sizes.
//
// The pairs checked (kCollisionPairs, built at compile time): every two links with a shape that are
// not parent and child (their boxes meet at the joint by design) and that have an IK joint on the
// tree path between them. The others are pruned: no joint the RC task moves changes their distance,
// so neither a row of the sub-task nor a stop of the RC task can change it (the tracks run along the
// chassis, touching it in the model at y = +-0.25 m; the head turns on the neck joints, which the
// operator moves).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/kinematics/jacobian.hpp"

namespace rescue::kin {

struct CollisionPair {
  std::uint8_t a;  // indices into desc::kCollisionShapes
  std::uint8_t b;
};

// True when IK column c's joint moves `link` (the joint's link is `link` or one of its ancestors).
constexpr bool moved_by_ik_joint(std::size_t column, std::size_t link) {
  // The joint's link is the ancestor asked about (not swapped).
  // NOLINTNEXTLINE(readability-suspicious-call-argument)
  return is_ancestor_or_self(kIkLink[column], link);
}

// An IK joint lies on the tree path between links a and b: it moves one and not the other.
constexpr bool ik_joint_between(std::size_t a, std::size_t b) {
  for (std::size_t c = 0; c < kIkLink.size(); ++c) {
    if (moved_by_ik_joint(c, a) != moved_by_ik_joint(c, b)) return true;
  }
  return false;
}

constexpr bool parent_and_child(std::size_t a, std::size_t b) {
  return desc::kLinks[a].parent == static_cast<int>(b) || desc::kLinks[b].parent == static_cast<int>(a);
}

constexpr bool checked_pair(std::size_t shape_a, std::size_t shape_b) {
  const auto a = static_cast<std::size_t>(desc::kCollisionShapes[shape_a].link);
  const auto b = static_cast<std::size_t>(desc::kCollisionShapes[shape_b].link);
  return !parent_and_child(a, b) && ik_joint_between(a, b);
}

constexpr std::size_t count_checked_pairs() {
  std::size_t n = 0;
  for (std::size_t a = 0; a < desc::kCollisionShapeCount; ++a) {
    for (std::size_t b = a + 1; b < desc::kCollisionShapeCount; ++b) n += checked_pair(a, b) ? 1U : 0U;
  }
  return n;
}
constexpr std::size_t kCollisionPairCount = count_checked_pairs();
static_assert(desc::kCollisionShapeCount <= 255, "shape indices are 8-bit");

constexpr std::array<CollisionPair, kCollisionPairCount> make_checked_pairs() {
  std::array<CollisionPair, kCollisionPairCount> pairs{};
  std::size_t n = 0;
  for (std::size_t a = 0; a < desc::kCollisionShapeCount; ++a) {
    for (std::size_t b = a + 1; b < desc::kCollisionShapeCount; ++b) {
      if (checked_pair(a, b)) pairs[n++] = {static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b)};
    }
  }
  return pairs;
}
constexpr std::array<CollisionPair, kCollisionPairCount> kCollisionPairs = make_checked_pairs();

inline const char* shape_link_name(std::size_t shape) noexcept {
  return desc::kLinks[static_cast<std::size_t>(desc::kCollisionShapes[shape].link)].name;
}

// Distance of one pair at the given link poses.
struct PairDistance {
  double distance_m{0.0};     // 0 when the shapes overlap (or touch)
  Vector3 on_a{Vector3::Zero()};  // closest points in base_link (the shapes' centres when overlapping)
  Vector3 on_b{Vector3::Zero()};
  bool overlapping{false};
};
PairDistance pair_distance(const LinkPoses& poses, const CollisionPair& pair) noexcept;

// The clearance the sub-task keeps (IkSettings::clearance).
struct ClearanceSettings {
  double activation_m{0.02};  // pairs closer than this get a repulsive row
  double stop_m{0.005};       // a pair closer than this: the sub-task could not keep the clearance
  double gain{0.05};          // share of (activation - distance) asked for per step
  double weight{5.0};         // weight of the rows among the sub-tasks
};

struct SelfCollisionReport {
  int close_pairs{0};               // pairs within the activation distance
  int closest_pair{-1};             // index into kCollisionPairs of the closest of them (-1: none close)
  double closest_distance_m{0.0};   // its distance (meaningful only when close_pairs > 0)
  bool stop{false};                 // a pair is closer than stop_m: the RC task must stop its motion
};

// The stop's reason for the RC task's log and the operator: "self-collision: LINK/LINK 0.00499 m <
// 0.00500 m" (the closest pair), "" without a stop. Returns `out`; never writes more than `size` bytes.
const char* stop_reason(const SelfCollisionReport& report, const ClearanceSettings& settings, char* out,
                        std::size_t size) noexcept;

constexpr int kClearanceRows = 4;  // rows for the closest pairs; further close pairs wait their turn
using ClearanceRows = Eigen::Matrix<double, kClearanceRows, kIkDof>;
using ClearanceErrors = Eigen::Matrix<double, kClearanceRows, 1>;

// The clearance sub-task at `poses`: for the kClearanceRows closest pairs within the activation
// distance, row weight * dd/dq over the IK joints (the pair's closest points moved by the Jacobians
// of their links, along the line between them) and error weight * gain * (activation - d); the other
// rows are zero. Only IK joints appear: a pair of an arm and a track is avoided by the arm (and the
// waist) alone, a pair of the torso and a track by the waist alone.
SelfCollisionReport clearance_rows(const LinkPoses& poses, const ClearanceSettings& settings, ClearanceRows& rows,
                                   ClearanceErrors& errors) noexcept;

}  // namespace rescue::kin
