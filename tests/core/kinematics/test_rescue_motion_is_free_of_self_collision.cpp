// Self-collision, offline, in the URDF's own collision geometry: every link's <collision> box (read
// by urdfdom from the URDF file) placed by our forward kinematics, every pair of links that are not
// parent and child tested with FCL (Debian's libfcl-dev, tests only). The ready posture and every
// 10th period of the whole rescue motion (through the RC period, as the RC task runs it, with the
// person as payload) are free of self-collision, and so is the zero pose (q = 0, which every drive
// can command: 0 is within every joint's limits), with the hands open or closed: the arms hang
// beside the tracks (docs/kinematics.md), 2 cm clear of them.
#include <gtest/gtest.h>

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/kinematics/jacobian.hpp"
#include "core/kinematics/rc_period.hpp"
#include "tests/core/kinematics/fcl_collision_boxes.hpp"

namespace rescue::kin {
namespace {

using test::collision_boxes;
using test::CollisionBox;

bool adjacent(std::size_t a, std::size_t b) { return test::parent_or_child(a, b); }

// Overlapping pairs of link boxes at q, each as "a/b".
std::vector<std::string> overlapping_pairs(const std::vector<CollisionBox>& boxes, const JointVector& q) {
  LinkPoses poses;
  forward_kinematics(q, poses);
  std::vector<fcl::Transform3d> placed;
  for (const CollisionBox& box : boxes) {
    fcl::Transform3d link = fcl::Transform3d::Identity();
    link.linear() = poses[box.link].R;
    link.translation() = poses[box.link].p;
    placed.push_back(link * box.origin);
  }
  std::vector<std::string> pairs;
  for (std::size_t a = 0; a < boxes.size(); ++a) {
    for (std::size_t b = a + 1; b < boxes.size(); ++b) {
      if (adjacent(boxes[a].link, boxes[b].link)) continue;
      const fcl::CollisionObjectd first(boxes[a].shape, placed[a]);
      const fcl::CollisionObjectd second(boxes[b].shape, placed[b]);
      fcl::CollisionRequestd request;
      fcl::CollisionResultd result;
      if (fcl::collide(&first, &second, request, result) > 0) {
        pairs.push_back(std::string(desc::kLinks[boxes[a].link].name) + "/" + desc::kLinks[boxes[b].link].name);
      }
    }
  }
  return pairs;
}

// The smallest distance at q between an arm link's box and any box but its parent's or children's,
// and its pair (the base and the tracks touch by design: their faces meet at y = +-0.25 m).
bool arm_link(std::size_t link) {
  return is_ancestor_or_self(link_index("l_shoulder_link"), link) ||
         is_ancestor_or_self(link_index("r_shoulder_link"), link);
}

double smallest_distance(const std::vector<CollisionBox>& boxes, const JointVector& q, std::string& pair) {
  LinkPoses poses;
  forward_kinematics(q, poses);
  double smallest = 1e9;
  for (std::size_t a = 0; a < boxes.size(); ++a) {
    for (std::size_t b = a + 1; b < boxes.size(); ++b) {
      if (adjacent(boxes[a].link, boxes[b].link)) continue;
      if (!arm_link(boxes[a].link) && !arm_link(boxes[b].link)) continue;
      fcl::Transform3d ta = fcl::Transform3d::Identity();
      ta.linear() = poses[boxes[a].link].R;
      ta.translation() = poses[boxes[a].link].p;
      fcl::Transform3d tb = fcl::Transform3d::Identity();
      tb.linear() = poses[boxes[b].link].R;
      tb.translation() = poses[boxes[b].link].p;
      const fcl::CollisionObjectd first(boxes[a].shape, ta * boxes[a].origin);
      const fcl::CollisionObjectd second(boxes[b].shape, tb * boxes[b].origin);
      fcl::DistanceRequestd request;
      fcl::DistanceResultd result;
      const double d = fcl::distance(&first, &second, request, result);
      if (d < smallest) {
        smallest = d;
        pair = std::string(desc::kLinks[boxes[a].link].name) + "/" + desc::kLinks[boxes[b].link].name;
      }
    }
  }
  return smallest;
}

std::string joined(const std::vector<std::string>& pairs) {
  std::string out;
  for (const std::string& p : pairs) out += p + " ";
  return out;
}

TEST(SelfCollision, EveryLinkWithABoxIsChecked) {
  const std::vector<CollisionBox> boxes = collision_boxes();
  EXPECT_GE(boxes.size(), 20U);
  for (const CollisionBox& box : boxes) EXPECT_NE(box.link, kNoIndex);
}

TEST(SelfCollision, ZeroPoseIsFreeWithTheHandsOpenOrClosed) {
  const std::vector<CollisionBox> boxes = collision_boxes();
  const auto left = static_cast<Eigen::Index>(joint_index("l_hand"));
  const auto right = static_cast<Eigen::Index>(joint_index("r_hand"));
  for (const bool open : {false, true}) {
    JointVector q = JointVector::Zero();
    if (open) {
      q(left) = kJoints[static_cast<std::size_t>(left)].limits.position_max_rad;
      q(right) = kJoints[static_cast<std::size_t>(right)].limits.position_max_rad;
    }
    const std::vector<std::string> pairs = overlapping_pairs(boxes, q);
    std::string closest;
    const double clearance = smallest_distance(boxes, q, closest);
    std::printf("q = 0, hands %s: %zu overlapping pairs, smallest arm clearance %.4f m (%s)\n", open ? "open" : "closed",
                pairs.size(), clearance, closest.c_str());
    EXPECT_TRUE(pairs.empty()) << joined(pairs);
    EXPECT_GT(clearance, 0.015) << closest;
  }
}

TEST(SelfCollision, ReadyPostureAndTheWholeRescueMotionAreFree) {
  const std::vector<CollisionBox> boxes = collision_boxes();
  const std::vector<std::string> ready = overlapping_pairs(boxes, ready_posture());
  EXPECT_TRUE(ready.empty()) << "ready posture: " << joined(ready);
  RcPeriod rc(ready_posture());
  const int periods = static_cast<int>(rc.motion().duration_s() * 1000.0) + 1;
  int checked = 0;
  for (int k = 0; k < periods; ++k) {
    ASSERT_TRUE(rc.run(k * 0.001, 0, JointVector::Zero()).ok());
    if (k % 10 != 0) continue;
    ++checked;
    const std::vector<std::string> pairs = overlapping_pairs(boxes, rc.rescue_references());
    ASSERT_TRUE(pairs.empty()) << "t = " << k * 0.001 << " s: " << joined(pairs);
  }
  std::printf("rescue motion: %d postures checked, none in self-collision\n", checked);
}

}  // namespace
}  // namespace rescue::kin
