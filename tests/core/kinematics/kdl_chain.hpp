// Bench support (rescue-bench-rc-kdl only): the KDL chain of one of our arm chains, built from the
// generated description (core/robot/robot_description.hpp), so KDL times exactly our chain (seven
// segments, no fixed palm segment). Not an oracle: the tests build KDL from the URDF file with
// kdl_parser instead (urdf_oracle.hpp), sharing nothing with the generated table.
#pragma once

#include <kdl/chain.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#include "core/kinematics/kinematic_model.hpp"
#include "core/kinematics/pose.hpp"
#include "tests/core/kinematics/kdl_conversions.hpp"

namespace rescue::kin::test {

inline KDL::Frame kdl_origin(std::size_t link) {
  const desc::Link& d = desc::kLinks[link];
  return KDL::Frame(KDL::Vector(d.origin[0], d.origin[1], d.origin[2]));
}

// One KDL segment per moving link: its joint, then the next link's origin as f_tip; a leading
// fixed segment carries the first link's origin; fixed links fold into the previous f_tip.
inline KDL::Chain make_kdl_chain(const Chain& chain) {
  KDL::Chain out;
  KDL::Frame pending = kdl_origin(chain.links[0]);
  bool first = true;
  std::size_t k = 0;
  while (k < chain.size) {
    const std::size_t link = chain.links[k];
    const desc::Link& d = desc::kLinks[link];
    if (first) {
      out.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), pending));
      first = false;
    }
    KDL::Frame tip = KDL::Frame::Identity();
    std::size_t next = k + 1;
    while (next < chain.size && kLinkJoint[chain.links[next]] == kNoIndex) {  // fold fixed links
      tip = tip * kdl_origin(chain.links[next]);
      ++next;
    }
    if (next < chain.size) tip = tip * kdl_origin(chain.links[next]);
    const KDL::Joint::JointType types[3] = {KDL::Joint::RotX, KDL::Joint::RotY, KDL::Joint::RotZ};
    out.addSegment(KDL::Segment(d.name, KDL::Joint(d.joint, types[d.axis], d.axis_sign), tip));
    k = next;
  }
  return out;
}

inline KDL::JntArray to_kdl(const ArmVector& q) {
  KDL::JntArray out(kArmJoints);
  for (int i = 0; i < kArmJoints; ++i) out(static_cast<unsigned>(i)) = q(i);
  return out;
}

}  // namespace rescue::kin::test
