#include "core/kinematics/centre_of_mass.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/kinematics/jacobian.hpp"

namespace rescue::kin {
namespace {

// Mass and first moment (sum m_i c_i) of each link's subtree, payload shares included.
struct Moments {
  std::array<double, kLinkCount> mass;
  std::array<Vector3, kLinkCount> moment;
};

void subtree_moments(const LinkPoses& poses, double payload_kg, Moments& m) noexcept {
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    const desc::Link& d = desc::kLinks[i];
    m.mass[i] = d.mass;
    m.moment[i] = d.mass * poses[i].apply(Vector3(d.com[0], d.com[1], d.com[2]));
  }
  const double half = 0.5 * payload_kg;
  m.mass[kLeftEe] += half;
  m.moment[kLeftEe] += half * poses[kLeftEe].p;
  m.mass[kRightEe] += half;
  m.moment[kRightEe] += half * poses[kRightEe].p;
  for (std::size_t i = kLinkCount - 1; i > 0; --i) {  // children come after their parents
    const auto parent = static_cast<std::size_t>(desc::kLinks[i].parent);
    m.mass[parent] += m.mass[i];
    m.moment[parent] += m.moment[i];
  }
}


}  // namespace

CentreOfMass centre_of_mass(const LinkPoses& poses, double payload_kg) noexcept {
  Vector3 moment = Vector3::Zero();
  double mass = 0.0;
  for (std::size_t i = 0; i < kLinkCount; ++i) {
    const desc::Link& d = desc::kLinks[i];
    moment += d.mass * poses[i].apply(Vector3(d.com[0], d.com[1], d.com[2]));
    mass += d.mass;
  }
  const double half = 0.5 * payload_kg;
  moment += half * (poses[kLeftEe].p + poses[kRightEe].p);
  mass += payload_kg;
  return CentreOfMass{moment / mass, mass};
}

void centre_of_mass_jacobian(const LinkPoses& poses, double payload_kg, IkJacobian3& jacobian) noexcept {
  Moments m;
  subtree_moments(poses, payload_kg, m);
  const double total = m.mass[0];
  for (std::size_t c = 0; c < kIkLink.size(); ++c) {
    const std::size_t link = kIkLink[c];
    const Vector3 w = joint_axis(poses[link], link);
    jacobian.col(static_cast<Eigen::Index>(c)) = w.cross(m.moment[link] - m.mass[link] * poses[link].p) / total;
  }
}

Eigen::Vector2d support_centre() noexcept {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const auto& corner : desc::kSupportPolygon) centre += Eigen::Vector2d(corner[0], corner[1]);
  return centre / static_cast<double>(desc::kSupportCorners);
}

double support_margin(const Vector3& com) noexcept {
  // Convex, counter-clockwise: the distance to the nearest edge line, negative when outside one.
  double margin = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < desc::kSupportCorners; ++i) {
    const auto& a = desc::kSupportPolygon[i];
    const auto& b = desc::kSupportPolygon[(i + 1) % desc::kSupportCorners];
    const double ex = b[0] - a[0];
    const double ey = b[1] - a[1];
    const double length = std::hypot(ex, ey);
    const double inside = (ex * (com.y() - a[1]) - ey * (com.x() - a[0])) / length;
    margin = std::min(margin, inside);
  }
  return margin;
}

}  // namespace rescue::kin
