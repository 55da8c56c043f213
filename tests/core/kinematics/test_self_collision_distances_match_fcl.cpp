// The self-collision model's distances (core/kinematics/self_collision.hpp) against FCL (Debian's
// libfcl-dev, tests only) on shapes built from the URDF file by urdfdom (nothing from the generated
// description): every checked pair at random postures over every joint's range (tracks over the
// whole turn, legs over their range, the waist beyond the 0.197 rad where the torso meets a turned
// track), boxes as FCL boxes, a track's envelope as an FCL cylinder. The envelope is exactly the
// track's box swept over the turn (its distance is the smallest box distance over the angles), the
// pair list is the documented one, and the report finds every pair within the activation distance.
#include <gtest/gtest.h>

#include <fcl/geometry/shape/cylinder.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <string>

#include "core/kinematics/self_collision.hpp"
#include "tests/core/kinematics/fcl_collision_boxes.hpp"
#include "tests/core/kinematics/random_configurations.hpp"

namespace rescue::kin {
namespace {

// m, ours against the smaller of FCL's two GJK solvers' distances (each stops at its own tolerance,
// 1e-6 relative; alone, libccd's was up to 4.5e-6 m and FCL's own 1.5e-5 m above ours)
constexpr double kTolerance = 2e-6;

// FCL shapes by link, from urdfdom: the box, or for a link its continuous joint turns, the cylinder
// its box sweeps about the joint's axis (through the link origin).
struct Oracle {
  std::vector<test::CollisionBox> boxes = test::collision_boxes();
  std::vector<std::shared_ptr<fcl::CollisionGeometryd>> geometry;  // per box: what the model checks
  std::vector<Eigen::Isometry3d> origin;                           // that geometry in the link frame
  std::vector<bool> envelope;

  Oracle() {
    const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(test::robot_urdf_text());
    for (const test::CollisionBox& box : boxes) {
      const urdf::JointConstSharedPtr joint = model->getLink(desc::kLinks[box.link].name)->parent_joint;
      const bool turns = joint && joint->type == urdf::Joint::CONTINUOUS;
      envelope.push_back(turns);
      if (!turns) {
        geometry.push_back(box.shape);
        origin.push_back(box.origin);
        continue;
      }
      const Eigen::Vector3d axis(joint->axis.x, joint->axis.y, joint->axis.z);
      double radius = 0.0;
      for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3d local((corner & 1 ? 0.5 : -0.5) * box.size.x(), (corner & 2 ? 0.5 : -0.5) * box.size.y(),
                                    (corner & 4 ? 0.5 : -0.5) * box.size.z());
        const Eigen::Vector3d p = box.origin * local;
        radius = std::max(radius, (p - p.dot(axis) * axis).norm());
      }
      const double length = std::fabs(box.size.dot(axis));
      geometry.push_back(std::make_shared<fcl::Cylinderd>(radius, length));
      Eigen::Isometry3d o = Eigen::Isometry3d::Identity();
      o.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix();
      o.translation() = box.origin.translation().dot(axis) * axis;
      origin.push_back(o);
    }
  }

  std::size_t of_link(std::size_t link) const {
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      if (boxes[i].link == link) return i;
    }
    return boxes.size();
  }

  // FCL's distance of two shapes (-1 when they collide, as FCL reports it): the smaller of its two
  // GJK solvers' (each stops at its own tolerance, so each may be above the distance, never below).
  double distance(const LinkPoses& poses, std::size_t a, std::size_t b) const {
    const fcl::CollisionObjectd first(geometry[a], test::link_transform(poses, boxes[a].link) * origin[a]);
    const fcl::CollisionObjectd second(geometry[b], test::link_transform(poses, boxes[b].link) * origin[b]);
    double best = 1e9;
    for (const fcl::GJKSolverType solver : {fcl::GST_LIBCCD, fcl::GST_INDEP}) {
      fcl::DistanceRequestd request;
      request.gjk_solver_type = solver;
      fcl::DistanceResultd result;
      best = std::min(best, fcl::distance(&first, &second, request, result));
    }
    return best;
  }
};

std::size_t shape_link(std::size_t shape) { return static_cast<std::size_t>(desc::kCollisionShapes[shape].link); }

// How far a point lies outside a shape (placed by our FK: the model's own shape, a box or a cylinder).
double outside(const LinkPoses& poses, std::size_t shape, const Vector3& point) {
  const desc::CollisionShape& d = desc::kCollisionShapes[shape];
  const Pose& link = poses[static_cast<std::size_t>(d.link)];
  const Vector3 local = link.R.transpose() * (point - link.p) - Vector3(d.centre[0], d.centre[1], d.centre[2]);
  const Vector3 half(d.half[0], d.half[1], d.half[2]);
  if (d.envelope_axis < 0) return ((local.cwiseAbs() - half).cwiseMax(0.0)).norm();
  const auto axis = static_cast<Eigen::Index>(d.envelope_axis);
  Vector3 radial = local;
  radial(axis) = 0.0;
  return std::max(std::fabs(local(axis)) - half(axis), 0.0) + std::max(radial.norm() - d.radius, 0.0);
}

// Random postures over every joint's range; a third with the waist in 0.15 .. 0.35 rad (after a cut).
JointVector posture(std::mt19937_64& rng, int k) {
  JointVector q = test::random_configuration(rng);
  if (k % 3 == 0) q(static_cast<Eigen::Index>(joint_index("waist_yaw"))) = std::uniform_real_distribution<double>(0.15, 0.35)(rng);
  return q;
}

TEST(SelfCollisionModel, EveryShapeIsAUrdfBoxAndTheTracksAreEnvelopes) {
  const Oracle oracle;
  ASSERT_EQ(oracle.boxes.size(), desc::kCollisionShapeCount);
  for (std::size_t s = 0; s < desc::kCollisionShapeCount; ++s) {
    const std::size_t i = oracle.of_link(shape_link(s));
    ASSERT_LT(i, oracle.boxes.size()) << shape_link_name(s);
    EXPECT_EQ(oracle.envelope[i], desc::kCollisionShapes[s].envelope_axis >= 0) << shape_link_name(s);
  }
}

TEST(SelfCollisionModel, PairsAreEveryPairButParentAndChildAndThoseNoIkJointMoves) {
  std::set<std::string> pruned;
  std::size_t checked = 0;
  for (std::size_t a = 0; a < desc::kCollisionShapeCount; ++a) {
    for (std::size_t b = a + 1; b < desc::kCollisionShapeCount; ++b) {
      const bool in_list = std::any_of(kCollisionPairs.begin(), kCollisionPairs.end(),
                                       [&](const CollisionPair& p) { return p.a == a && p.b == b; });
      checked += in_list ? 1U : 0U;
      if (test::parent_or_child(shape_link(a), shape_link(b))) {
        EXPECT_FALSE(in_list) << shape_link_name(a) << "/" << shape_link_name(b);
      } else if (!in_list) {
        pruned.insert(std::string(shape_link_name(a)) + "/" + shape_link_name(b));
      }
    }
  }
  // Pruned beyond parent and child: the lower body's pairs (legs and tracks on the base) and the
  // torso with the head (turned by the neck): no IK joint between them.
  const std::set<std::string> expected{"base_link/l_track_link", "base_link/r_track_link", "l_leg_link/r_leg_link",
                                       "l_leg_link/r_track_link", "r_leg_link/l_track_link", "l_track_link/r_track_link",
                                       "torso_link/head_link"};
  EXPECT_EQ(pruned, expected);
  EXPECT_EQ(checked, kCollisionPairCount);
  std::printf("%zu shapes, %zu pairs checked, %zu pruned beyond parent and child\n", desc::kCollisionShapeCount,
              kCollisionPairCount, pruned.size());
}

TEST(SelfCollisionModel, DistancesAgreeWithFclAtRandomPostures) {
  const Oracle oracle;
  std::mt19937_64 rng(33);
  LinkPoses poses;
  double largest_difference = 0.0;
  double largest_above = -1.0;  // ours - FCL's
  int differing = 0;
  int compared = 0;
  int overlapping = 0;
  for (int k = 0; k < 300; ++k) {
    forward_kinematics(posture(rng, k), poses);
    for (const CollisionPair& pair : kCollisionPairs) {
      const PairDistance ours = pair_distance(poses, pair);
      const double theirs = oracle.distance(poses, oracle.of_link(shape_link(pair.a)), oracle.of_link(shape_link(pair.b)));
      if (theirs <= 0.0 || ours.overlapping) {
        // Both must say so, unless the shapes are within the tolerance of touching.
        EXPECT_TRUE((theirs <= 0.0 && ours.overlapping) || std::max(theirs, ours.distance_m) < kTolerance)
            << shape_link_name(pair.a) << "/" << shape_link_name(pair.b) << " FCL " << theirs << " ours "
            << ours.distance_m;
        ++overlapping;
        continue;
      }
      ++compared;
      largest_difference = std::max(largest_difference, std::fabs(ours.distance_m - theirs));
      largest_above = std::max(largest_above, ours.distance_m - theirs);
      if (std::fabs(ours.distance_m - theirs) > 1e-9) ++differing;
      EXPECT_LT(ours.distance_m - theirs, 1e-9) << "never above FCL's";
      EXPECT_NEAR(ours.distance_m, theirs, kTolerance) << shape_link_name(pair.a) << "/" << shape_link_name(pair.b);
      // The closest points are that far apart and lie on their shapes: ours is a distance attained.
      EXPECT_NEAR((ours.on_a - ours.on_b).norm(), ours.distance_m, 1e-12);
      EXPECT_LT(outside(poses, pair.a, ours.on_a), 1e-9) << shape_link_name(pair.a);
      EXPECT_LT(outside(poses, pair.b, ours.on_b), 1e-9) << shape_link_name(pair.b);
    }
  }
  std::printf("%d distances compared with FCL, largest difference %.3g m (ours - FCL's at most %.3g m), %d differ "
              "by more than 1e-9 m; %d overlapping pairs agreed\n",
              compared, largest_difference, largest_above, differing, overlapping);
  EXPECT_GT(compared, 50000);
  EXPECT_GT(overlapping, 300);
}

TEST(SelfCollisionModel, TheEnvelopeIsTheTrackBoxSweptOverTheTurn) {
  const Oracle oracle;
  std::mt19937_64 rng(7);
  LinkPoses poses;
  double largest_gap = 0.0;
  int pairs = 0;
  for (int k = 0; k < 6; ++k) {
    JointVector q = posture(rng, k);
    forward_kinematics(q, poses);
    for (const CollisionPair& pair : kCollisionPairs) {
      const bool a_turns = desc::kCollisionShapes[pair.a].envelope_axis >= 0;
      if (!a_turns && desc::kCollisionShapes[pair.b].envelope_axis < 0) continue;
      const PairDistance ours = pair_distance(poses, pair);
      if (ours.overlapping) continue;
      const std::size_t track_link = shape_link(a_turns ? pair.a : pair.b);
      const std::size_t other = oracle.of_link(shape_link(a_turns ? pair.b : pair.a));
      const std::size_t track = oracle.of_link(track_link);
      // The track's real box at 720 angles over the turn: never closer than the envelope, and as
      // close at the nearest angle.
      double nearest = 1e9;
      JointVector turned = q;
      LinkPoses turned_poses;
      for (int step = 0; step < 720; ++step) {
        turned(static_cast<Eigen::Index>(kLinkJoint[track_link])) = step * (2.0 * M_PI / 720.0);
        forward_kinematics(turned, turned_poses);
        const fcl::CollisionObjectd box(oracle.boxes[track].shape,
                                        test::link_transform(turned_poses, track_link) * oracle.boxes[track].origin);
        const fcl::CollisionObjectd shape(oracle.geometry[other], test::link_transform(turned_poses, oracle.boxes[other].link) *
                                                                       oracle.origin[other]);
        fcl::DistanceRequestd request;
        fcl::DistanceResultd result;
        const double d = fcl::distance(&box, &shape, request, result);
        nearest = std::min(nearest, d < 0.0 ? 0.0 : d);
        ASSERT_GE(d < 0.0 ? 0.0 : d, ours.distance_m - kTolerance) << "the envelope must hold the box at every angle";
      }
      largest_gap = std::max(largest_gap, nearest - ours.distance_m);
      ++pairs;
    }
  }
  std::printf("%d track pairs: the box over 720 angles comes within %.3g m of the envelope's distance\n", pairs,
              largest_gap);
  EXPECT_LT(largest_gap, 1e-3);  // the angle sampling's error (0.5 degree at up to 0.52 m)
  EXPECT_GT(pairs, 100);
}

TEST(SelfCollisionModel, TheReportFindsEveryPairWithinTheActivationDistance) {
  const Oracle oracle;
  const ClearanceSettings settings;
  std::mt19937_64 rng(5);
  LinkPoses poses;
  ClearanceRows rows;
  ClearanceErrors errors;
  for (int k = 0; k < 300; ++k) {
    forward_kinematics(posture(rng, k), poses);
    int close = 0;
    bool stop = false;
    double nearest = 1e9;
    for (const CollisionPair& pair : kCollisionPairs) {
      const double d = std::max(0.0, oracle.distance(poses, oracle.of_link(shape_link(pair.a)), oracle.of_link(shape_link(pair.b))));
      if (d >= settings.activation_m) continue;
      ++close;
      stop = stop || d < settings.stop_m;
      nearest = std::min(nearest, d);
    }
    const SelfCollisionReport report = clearance_rows(poses, settings, rows, errors);
    ASSERT_EQ(report.close_pairs, close) << "posture " << k;
    ASSERT_EQ(report.stop, stop) << "posture " << k;
    if (close > 0) {
      ASSERT_NEAR(report.closest_distance_m, nearest, kTolerance);
    } else {
      EXPECT_EQ(report.closest_pair, -1);
      EXPECT_TRUE(rows.isZero() && errors.isZero());
    }
  }
}

}  // namespace
}  // namespace rescue::kin
