#include "core/kinematics/self_collision.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rescue::kin {
namespace {

using IkRow = Eigen::Matrix<double, 1, kIkDof>;

// A shape placed in base_link: a box (centre c, axes R's columns, half sizes h) or a cylinder about
// R's column `axis` (radius, half-length h(axis)); h of a cylinder is its bounding box's.
struct PlacedShape {
  Vector3 c;
  Matrix3 R;
  Vector3 h;
  int axis;
  double radius;
  double bound;  // bounding sphere's radius about c
};

PlacedShape place(const LinkPoses& poses, std::size_t shape) noexcept {
  const desc::CollisionShape& d = desc::kCollisionShapes[shape];
  const Pose& link = poses[static_cast<std::size_t>(d.link)];
  PlacedShape s;
  s.R = link.R;
  s.c = link.p + link.R * Vector3(d.centre[0], d.centre[1], d.centre[2]);
  s.axis = d.envelope_axis;
  s.radius = d.radius;
  s.h = Vector3(d.half[0], d.half[1], d.half[2]);
  if (s.axis >= 0) {
    s.h.setConstant(d.radius);
    s.h(s.axis) = d.half[s.axis];
  }
  s.bound = d.bound;
  return s;
}

// The shape's point furthest along d.
Vector3 support(const PlacedShape& s, const Vector3& d) noexcept {
  if (s.axis < 0) {
    const Vector3 local = s.R.transpose() * d;
    Vector3 out = s.c;
    for (int k = 0; k < 3; ++k) out += s.R.col(k) * (local(k) >= 0.0 ? s.h(k) : -s.h(k));
    return out;
  }
  const Vector3 u = s.R.col(s.axis);
  const double along = d.dot(u);
  Vector3 out = s.c + (along >= 0.0 ? s.h(s.axis) : -s.h(s.axis)) * u;
  const Vector3 radial = d - along * u;
  const double n = radial.norm();
  if (n > 1e-12 * d.norm()) out += (s.radius / n) * radial;
  return out;
}

// A lower bound of the distance: the largest gap between the shapes' (bounding) boxes along the
// six face normals. Cheap, and it rules most far pairs out before the exact distance.
double face_axis_gap(const PlacedShape& a, const PlacedShape& b) noexcept {
  const Vector3 t = b.c - a.c;
  const Matrix3 c = a.R.transpose() * b.R;  // b's axes in a's frame
  double gap = -1.0;
  for (int i = 0; i < 3; ++i) {
    const double ra = a.h(i);
    const double rb = std::fabs(c(i, 0)) * b.h(0) + std::fabs(c(i, 1)) * b.h(1) + std::fabs(c(i, 2)) * b.h(2);
    gap = std::max(gap, std::fabs(a.R.col(i).dot(t)) - ra - rb);
    const double ra2 = std::fabs(c(0, i)) * a.h(0) + std::fabs(c(1, i)) * a.h(1) + std::fabs(c(2, i)) * a.h(2);
    gap = std::max(gap, std::fabs(b.R.col(i).dot(t)) - ra2 - b.h(i));
  }
  return gap;
}

// ---- GJK: the point of the Minkowski difference A - B closest to the origin ----
struct Vertex {
  Vector3 w;  // a - b
  Vector3 a;
  Vector3 b;
};

struct Simplex {
  std::array<Vertex, 4> v;
  std::array<double, 4> lambda{};
  int n{0};

  // Keeps the vertices with a positive weight.
  void keep(const std::array<double, 4>& weights, int count) noexcept {
    int k = 0;
    for (int i = 0; i < count; ++i) {
      if (weights[static_cast<std::size_t>(i)] <= 0.0) continue;
      v[static_cast<std::size_t>(k)] = v[static_cast<std::size_t>(i)];
      lambda[static_cast<std::size_t>(k)] = weights[static_cast<std::size_t>(i)];
      ++k;
    }
    n = k;
  }
};

// Barycentric weights of the point of triangle (a, b, c) closest to the origin (Ericson,
// Real-Time Collision Detection 5.1.5).
std::array<double, 4> closest_on_triangle(const Vector3& a, const Vector3& b, const Vector3& c) noexcept {
  const Vector3 ab = b - a;
  const Vector3 ac = c - a;
  const double d1 = -ab.dot(a);
  const double d2 = -ac.dot(a);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0, 0.0};
  const double d3 = -ab.dot(b);
  const double d4 = -ac.dot(b);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double t = d1 / (d1 - d3);
    return {1.0 - t, t, 0.0, 0.0};
  }
  const double d5 = -ab.dot(c);
  const double d6 = -ac.dot(c);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0, 0.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double t = d2 / (d2 - d6);
    return {1.0 - t, 0.0, t, 0.0};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - t, t, 0.0};
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom;
  const double w = vc * denom;
  return {1.0 - v - w, v, w, 0.0};
}

Vector3 combine(const Simplex& s, const std::array<double, 4>& weights, int count) noexcept {
  Vector3 p = Vector3::Zero();
  for (int i = 0; i < count; ++i) p += weights[static_cast<std::size_t>(i)] * s.v[static_cast<std::size_t>(i)].w;
  return p;
}

// Reduces the simplex to the smallest face holding its point closest to the origin and returns
// that point; false when the origin is inside the tetrahedron (the shapes overlap).
bool reduce(Simplex& s, Vector3& closest) noexcept {
  std::array<double, 4> weights{1.0, 0.0, 0.0, 0.0};
  if (s.n == 2) {
    const Vector3& a = s.v[0].w;
    const Vector3 ab = s.v[1].w - a;
    const double length2 = ab.squaredNorm();
    const double t = length2 > 0.0 ? std::clamp(-a.dot(ab) / length2, 0.0, 1.0) : 0.0;
    weights = {1.0 - t, t, 0.0, 0.0};
    if (t >= 1.0) weights = {0.0, 1.0, 0.0, 0.0};
  } else if (s.n == 3) {
    weights = closest_on_triangle(s.v[0].w, s.v[1].w, s.v[2].w);
  } else if (s.n == 4) {
    // Each face the origin lies outside of (on the side away from the fourth vertex) may hold the
    // closest point; none: the origin is inside. A flat tetrahedron counts every face as outside.
    static constexpr std::array<std::array<int, 4>, 4> kFaces{{{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}}};
    double best = -1.0;
    for (const std::array<int, 4>& f : kFaces) {
      const Vector3& a = s.v[static_cast<std::size_t>(f[0])].w;
      const Vector3& b = s.v[static_cast<std::size_t>(f[1])].w;
      const Vector3& c = s.v[static_cast<std::size_t>(f[2])].w;
      const Vector3& d = s.v[static_cast<std::size_t>(f[3])].w;
      const Vector3 normal = (b - a).cross(c - a);
      const double side_origin = -a.dot(normal);
      const double side_fourth = (d - a).dot(normal);
      const bool flat = std::fabs(side_fourth) <= 1e-14 * std::max(1.0, normal.squaredNorm());
      if (!flat && side_origin * side_fourth >= 0.0) continue;
      const std::array<double, 4> face = closest_on_triangle(a, b, c);
      const Vector3 p = face[0] * a + face[1] * b + face[2] * c;
      const double distance2 = p.squaredNorm();
      if (best >= 0.0 && distance2 >= best) continue;
      best = distance2;
      weights = {0.0, 0.0, 0.0, 0.0};
      for (int k = 0; k < 3; ++k) weights[static_cast<std::size_t>(f[static_cast<std::size_t>(k)])] = face[static_cast<std::size_t>(k)];
    }
    if (best < 0.0) return false;
  }
  closest = combine(s, weights, s.n);
  s.keep(weights, s.n);
  return true;
}

PairDistance gjk(const PlacedShape& a, const PlacedShape& b) noexcept {
  constexpr int kMaxIterations = 64;
  constexpr double kRelativeTolerance = 1e-10;  // |v|^2 - v.w: distance known to ~1e-10 of itself
  constexpr double kTouching = 1e-9;            // m: closer counts as overlapping
  PairDistance out;
  Simplex s;
  Vector3 v = a.c - b.c;
  if (v.squaredNorm() == 0.0) v = Vector3::UnitX();
  bool overlap = false;
  for (int it = 0; it < kMaxIterations; ++it) {
    Vertex p;
    p.a = support(a, -v);
    p.b = support(b, v);
    p.w = p.a - p.b;
    const double v2 = v.squaredNorm();
    if (s.n > 0 && v2 - v.dot(p.w) <= kRelativeTolerance * v2) break;  // no support point is closer
    bool repeated = false;
    for (int i = 0; i < s.n; ++i) repeated = repeated || (s.v[static_cast<std::size_t>(i)].w - p.w).squaredNorm() == 0.0;
    if (repeated) break;
    s.v[static_cast<std::size_t>(s.n++)] = p;
    Vector3 next;
    if (!reduce(s, next)) {
      overlap = true;
      break;
    }
    if (next.squaredNorm() <= kTouching * kTouching) {
      overlap = true;
      break;
    }
    if (s.n > 1 && next.squaredNorm() >= v2) break;  // rounding: no more progress
    v = next;
  }
  if (overlap) {
    out.overlapping = true;
    out.on_a = a.c;
    out.on_b = b.c;
    return out;
  }
  for (int i = 0; i < s.n; ++i) {
    out.on_a += s.lambda[static_cast<std::size_t>(i)] * s.v[static_cast<std::size_t>(i)].a;
    out.on_b += s.lambda[static_cast<std::size_t>(i)] * s.v[static_cast<std::size_t>(i)].b;
  }
  out.distance_m = (out.on_a - out.on_b).norm();
  return out;
}

// dd/dq of a pair: the closest points, carried by their links, along the unit line between them.
IkRow distance_row(const LinkPoses& poses, std::size_t link_a, std::size_t link_b, const PairDistance& d) noexcept {
  Vector3 n = d.on_a - d.on_b;
  const double length = n.norm();
  n = length > 0.0 ? Vector3(n / length) : Vector3::UnitZ();
  IkRow row = IkRow::Zero();
  for (std::size_t c = 0; c < kIkLink.size(); ++c) {
    const bool moves_a = moved_by_ik_joint(c, link_a);
    const bool moves_b = moved_by_ik_joint(c, link_b);
    if (moves_a == moves_b) continue;  // turns both or neither: the distance stays
    const std::size_t link = kIkLink[c];
    const Vector3 w = joint_axis(poses[link], link);
    const Vector3 point = moves_a ? d.on_a : d.on_b;
    const double along = n.dot(w.cross(point - poses[link].p));
    row(static_cast<Eigen::Index>(c)) = moves_a ? along : -along;
  }
  return row;
}

}  // namespace

PairDistance pair_distance(const LinkPoses& poses, const CollisionPair& pair) noexcept {
  return gjk(place(poses, pair.a), place(poses, pair.b));
}

const char* stop_reason(const SelfCollisionReport& report, const ClearanceSettings& settings, char* out,
                        std::size_t size) noexcept {
  if (size == 0) return out;
  out[0] = '\0';
  if (!report.stop || report.closest_pair < 0 || static_cast<std::size_t>(report.closest_pair) >= kCollisionPairs.size()) {
    return out;
  }
  const CollisionPair& pair = kCollisionPairs[static_cast<std::size_t>(report.closest_pair)];
  (void)std::snprintf(out, size, "self-collision: %s/%s %.5f m < %.5f m", shape_link_name(pair.a),
                      shape_link_name(pair.b), report.closest_distance_m, settings.stop_m);
  return out;
}

SelfCollisionReport clearance_rows(const LinkPoses& poses, const ClearanceSettings& settings, ClearanceRows& rows,
                                   ClearanceErrors& errors) noexcept {
  std::array<PlacedShape, desc::kCollisionShapeCount> placed;
  for (std::size_t i = 0; i < placed.size(); ++i) placed[i] = place(poses, i);
  struct Close {
    std::size_t pair;
    PairDistance distance;
  };
  std::array<Close, kClearanceRows> closest{};
  int kept = 0;
  SelfCollisionReport report;
  for (std::size_t k = 0; k < kCollisionPairs.size(); ++k) {
    const PlacedShape& a = placed[kCollisionPairs[k].a];
    const PlacedShape& b = placed[kCollisionPairs[k].b];
    const double reach = a.bound + b.bound + settings.activation_m;
    if ((a.c - b.c).squaredNorm() >= reach * reach) continue;
    if (face_axis_gap(a, b) >= settings.activation_m) continue;
    const PairDistance d = gjk(a, b);
    if (d.distance_m >= settings.activation_m) continue;
    ++report.close_pairs;
    report.stop = report.stop || d.distance_m < settings.stop_m;
    // Insert among the closest kClearanceRows (sorted, nearest first).
    int at = kept;
    while (at > 0 && closest[static_cast<std::size_t>(at - 1)].distance.distance_m > d.distance_m) --at;
    if (at >= kClearanceRows) continue;
    for (int i = std::min(kept, kClearanceRows - 1); i > at; --i) {
      closest[static_cast<std::size_t>(i)] = closest[static_cast<std::size_t>(i - 1)];
    }
    closest[static_cast<std::size_t>(at)] = {k, d};
    kept = std::min(kept + 1, kClearanceRows);
  }
  rows.setZero();
  errors.setZero();
  for (int i = 0; i < kept; ++i) {
    const Close& c = closest[static_cast<std::size_t>(i)];
    const auto link_a = static_cast<std::size_t>(desc::kCollisionShapes[kCollisionPairs[c.pair].a].link);
    const auto link_b = static_cast<std::size_t>(desc::kCollisionShapes[kCollisionPairs[c.pair].b].link);
    rows.row(i) = settings.weight * distance_row(poses, link_a, link_b, c.distance);
    errors(i) = settings.weight * settings.gain * (settings.activation_m - c.distance.distance_m);
  }
  if (kept > 0) {
    report.closest_pair = static_cast<int>(closest[0].pair);
    report.closest_distance_m = closest[0].distance.distance_m;
  }
  return report;
}

}  // namespace rescue::kin
