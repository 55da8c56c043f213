// Test support: the URDF's <collision> boxes as FCL shapes, read by urdfdom from the URDF file (the
// oracle shares nothing with the generated description), placed in base_link by link poses.
#pragma once

#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>

#include <memory>
#include <vector>

#include "core/kinematics/forward_kinematics.hpp"
#include "tests/core/kinematics/urdf_oracle.hpp"

namespace rescue::kin::test {

struct CollisionBox {
  std::size_t link;
  std::shared_ptr<fcl::Boxd> shape;
  Eigen::Isometry3d origin;  // box in the link frame
  Eigen::Vector3d size;
};

inline std::vector<CollisionBox> collision_boxes(const std::string& urdf_text = robot_urdf_text()) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf_text);
  std::vector<CollisionBox> boxes;
  if (!model) return boxes;
  for (const auto& [name, link] : model->links_) {
    if (!link->collision || !link->collision->geometry || link->collision->geometry->type != urdf::Geometry::BOX) continue;
    const auto& box = static_cast<const urdf::Box&>(*link->collision->geometry);
    const urdf::Pose& o = link->collision->origin;
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
    origin.linear() = Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z).toRotationMatrix();
    origin.translation() = Eigen::Vector3d(o.position.x, o.position.y, o.position.z);
    boxes.push_back({link_index(name.c_str()), std::make_shared<fcl::Boxd>(box.dim.x, box.dim.y, box.dim.z), origin,
                     Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z)});
  }
  return boxes;
}

inline fcl::Transform3d link_transform(const LinkPoses& poses, std::size_t link) {
  fcl::Transform3d t = fcl::Transform3d::Identity();
  t.linear() = poses[link].R;
  t.translation() = poses[link].p;
  return t;
}

inline bool parent_or_child(std::size_t a, std::size_t b) {
  return desc::kLinks[a].parent == static_cast<int>(b) || desc::kLinks[b].parent == static_cast<int>(a);
}

}  // namespace rescue::kin::test
