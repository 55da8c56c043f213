// Test support: the independent oracle. Everything here comes from the URDF text itself, parsed by
// other people's code: the KDL tree by kdl_parser (Debian's libkdl-parser-dev: joint origins with
// their rotations, arbitrary joint axes), masses and centres of mass by urdfdom (liburdfdom-dev).
// Nothing is read from the generated description (core/robot/robot_description.hpp), so a mistake in
// turning the URDF into that table fails the tests that compare the two. Joints are matched by name
// only (the URDF's joint names are core/robot/robot.hpp's kJoints names).
#pragma once

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/tree.hpp>
#include <kdl/treefksolverpos_recursive.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/kinematics/kinematic_model.hpp"
#include "core/kinematics/pose.hpp"
#include "tests/core/kinematics/kdl_conversions.hpp"

namespace rescue::kin::test {

// The URDF the firmware's description is generated from (a compile definition of the tests).
inline std::string robot_urdf_text() {
  std::ifstream in(RESCUE_ROBOT_URDF);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The URDF with the first occurrence of `from` replaced by `to` (a mutant); empty if not found.
inline std::string mutate(const std::string& urdf, const std::string& from, const std::string& to) {
  const std::size_t at = urdf.find(from);
  if (at == std::string::npos) return {};
  std::string out = urdf;
  out.replace(at, from.size(), to);
  return out;
}

class UrdfOracle {
 public:
  // Parses `urdf` with kdl_parser and urdfdom; ok() false if either refuses it.
  explicit UrdfOracle(const std::string& urdf) {
    ok_ = kdl_parser::treeFromString(urdf, tree_);
    model_ = urdf::parseURDF(urdf);
    ok_ = ok_ && model_ != nullptr;
  }
  bool ok() const { return ok_; }
  const KDL::Tree& tree() const { return tree_; }

  // The chain from base_link to `tip` (a URDF link name), as kdl_parser built it.
  KDL::Chain chain(const char* tip) const {
    KDL::Chain out;
    (void)tree_.getChain("base_link", tip, out);
    return out;
  }

  // The chain's joint values taken, by joint name, from a whole-robot joint vector.
  static KDL::JntArray chain_joints(const KDL::Chain& chain, const JointVector& q) {
    KDL::JntArray out(chain.getNrOfJoints());
    unsigned k = 0;
    for (const KDL::Segment& s : chain.segments) {
      if (s.getJoint().getType() == KDL::Joint::None) continue;
      out(k++) = q(static_cast<Eigen::Index>(joint_index(s.getJoint().getName().c_str())));
    }
    return out;
  }

  // The tree's joint values, by joint name.
  KDL::JntArray tree_joints(const JointVector& q) const {
    KDL::JntArray out(tree_.getNrOfJoints());
    for (const auto& [name, element] : tree_.getSegments()) {
      const KDL::Joint& joint = GetTreeElementSegment(element).getJoint();
      if (joint.getType() == KDL::Joint::None) continue;
      out(GetTreeElementQNr(element)) = q(static_cast<Eigen::Index>(joint_index(joint.getName().c_str())));
    }
    return out;
  }

  // Pose of the URDF link `link` in base_link.
  Pose link_pose(const JointVector& q, const std::string& link) const {
    KDL::TreeFkSolverPos_recursive fk(tree_);
    KDL::Frame frame;
    if (link != "base_link") (void)fk.JntToCart(tree_joints(q), frame, link);
    return to_pose(frame);
  }

  // Total mass and centre of mass from urdfdom's <inertial> of every link (payload: half in each
  // palm, at the l_ee and r_ee frames).
  double mass() const {
    double m = 0.0;
    for (const auto& [name, link] : model_->links_) {
      if (link->inertial) m += link->inertial->mass;
    }
    return m;
  }
  Vector3 centre_of_mass(const JointVector& q, double payload_kg) const {
    KDL::TreeFkSolverPos_recursive fk(tree_);
    const KDL::JntArray joints = tree_joints(q);
    KDL::Vector moment = KDL::Vector::Zero();
    double m = 0.0;
    for (const auto& [name, link] : model_->links_) {
      if (!link->inertial) continue;
      KDL::Frame frame;
      if (name != "base_link") (void)fk.JntToCart(joints, frame, name);
      const urdf::Vector3& c = link->inertial->origin.position;
      moment += link->inertial->mass * (frame * KDL::Vector(c.x, c.y, c.z));
      m += link->inertial->mass;
    }
    for (const char* palm : {"l_ee", "r_ee"}) {
      KDL::Frame frame;
      (void)fk.JntToCart(joints, frame, palm);
      moment += 0.5 * payload_kg * frame.p;
    }
    moment = moment / (m + payload_kg);
    return Vector3(moment.x(), moment.y(), moment.z());
  }

 private:
  bool ok_{false};
  KDL::Tree tree_;
  urdf::ModelInterfaceSharedPtr model_;
};

}  // namespace rescue::kin::test
