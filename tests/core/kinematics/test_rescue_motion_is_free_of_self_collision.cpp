// Self-collision, offline, in the URDF's own collision geometry: every link's <collision> box (read
// by urdfdom from the URDF file) placed by our forward kinematics, every pair of links that are not
// parent and child tested with FCL (Debian's libfcl-dev, tests only). The ready posture and every
// 10th period of the whole rescue motion (through the RC period, as the RC task runs it, with the
// person as payload) are free of self-collision. The zero pose is not (the arms hang through the
// tracks, docs/kinematics.md): the test says how many pairs overlap there, so a change is seen.
#include <gtest/gtest.h>

#include <fcl/narrowphase/collision.h>
#include <fcl/geometry/shape/box.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/kinematics/rc_period.hpp"
#include "tests/core/kinematics/urdf_oracle.hpp"

namespace rescue::kin {
namespace {

struct CollisionBox {
  std::size_t link;
  std::shared_ptr<fcl::Boxd> shape;
  Eigen::Isometry3d origin;  // box in the link frame
};

std::vector<CollisionBox> collision_boxes() {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(test::robot_urdf_text());
  std::vector<CollisionBox> boxes;
  if (!model) return boxes;
  for (const auto& [name, link] : model->links_) {
    if (!link->collision || !link->collision->geometry || link->collision->geometry->type != urdf::Geometry::BOX) continue;
    const auto& box = static_cast<const urdf::Box&>(*link->collision->geometry);
    const urdf::Pose& o = link->collision->origin;
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
    origin.linear() = Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z).toRotationMatrix();
    origin.translation() = Eigen::Vector3d(o.position.x, o.position.y, o.position.z);
    boxes.push_back({link_index(name.c_str()), std::make_shared<fcl::Boxd>(box.dim.x, box.dim.y, box.dim.z), origin});
  }
  return boxes;
}

bool adjacent(std::size_t a, std::size_t b) {
  return desc::kLinks[a].parent == static_cast<int>(b) || desc::kLinks[b].parent == static_cast<int>(a);
}

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

TEST(SelfCollision, ZeroPoseOverlapsAreCounted) {
  const std::vector<std::string> pairs = overlapping_pairs(collision_boxes(), JointVector::Zero());
  std::printf("q = 0: %zu overlapping pairs: %s\n", pairs.size(), joined(pairs).c_str());
  EXPECT_EQ(pairs.size(), 14U) << "the zero pose's overlaps changed (docs/kinematics.md): " << joined(pairs);
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
