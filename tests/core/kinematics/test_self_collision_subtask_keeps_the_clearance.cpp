// The IK's self-collision sub-task (IkSettings::self_collision_task, on by default) and its stop:
// its rows are the distance's gradient over the IK joints (central differences); over the whole
// rescue motion, healthy and with link cuts at l_elbow / r_elbow at several times, with the tracks
// turning over the whole turn again and again and the legs sweeping their range (neither is an IK
// joint: the sub-task sees them as they are), every 10th posture the RC task would send has no
// overlapping pair of URDF boxes (FCL, on the tracks' real boxes at their angle): the sub-task keeps
// the clearance, or the report's stop comes first and the loop (as the RC task must) holds its
// references. With the sub-task and its stop off, a waist the palms' targets turn overlaps: the test bites.
#include <gtest/gtest.h>

#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/kinematics/rescue_motion.hpp"
#include "core/kinematics/self_collision.hpp"
#include "core/kinematics/task_shape.hpp"
#include "core/kinematics/task_priority_ik.hpp"
#include "tests/core/kinematics/fcl_collision_boxes.hpp"
#include "tests/core/kinematics/random_configurations.hpp"

namespace rescue::kin {
namespace {

const std::vector<test::CollisionBox>& boxes() {
  static const std::vector<test::CollisionBox> all = test::collision_boxes();
  return all;
}

std::size_t box_of_link(std::size_t link) {
  for (std::size_t i = 0; i < boxes().size(); ++i) {
    if (boxes()[i].link == link) return i;
  }
  return boxes().size();
}

// The checked pairs whose real URDF boxes overlap at q (FCL), as "a/b ".
std::string overlapping_pairs(const JointVector& q) {
  LinkPoses poses;
  forward_kinematics(q, poses);
  std::string pairs;
  for (const CollisionPair& pair : kCollisionPairs) {
    const test::CollisionBox& a = boxes()[box_of_link(static_cast<std::size_t>(desc::kCollisionShapes[pair.a].link))];
    const test::CollisionBox& b = boxes()[box_of_link(static_cast<std::size_t>(desc::kCollisionShapes[pair.b].link))];
    const fcl::CollisionObjectd first(a.shape, test::link_transform(poses, a.link) * a.origin);
    const fcl::CollisionObjectd second(b.shape, test::link_transform(poses, b.link) * b.origin);
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    if (fcl::collide(&first, &second, request, result) > 0) {
      pairs += std::string(shape_link_name(pair.a)) + "/" + shape_link_name(pair.b) + " ";
    }
  }
  return pairs;
}

TEST(ClearanceSubtask, RowsAreTheDistanceGradientOverTheIkJoints) {
  std::mt19937_64 rng(11);
  ClearanceSettings settings;
  settings.activation_m = 0.2;  // many close pairs to check
  LinkPoses poses;
  ClearanceRows rows;
  ClearanceErrors errors;
  int checked = 0;
  double largest = 0.0;
  for (int k = 0; k < 200 && checked < 300; ++k) {
    const JointVector q = test::random_configuration(rng, 0.05);
    forward_kinematics(q, poses);
    const SelfCollisionReport report = clearance_rows(poses, settings, rows, errors);
    if (report.close_pairs == 0 || report.closest_distance_m < 1e-3) continue;  // gradients of separated pairs
    const CollisionPair pair = kCollisionPairs[static_cast<std::size_t>(report.closest_pair)];
    constexpr double h = 1e-5;  // the distance is exact to ~1e-10 m: noise 1e-5, truncation below
    for (std::size_t c = 0; c < kIkJoints.size(); ++c) {
      JointVector plus = q;
      JointVector minus = q;
      plus(static_cast<Eigen::Index>(kIkJoints[c])) += h;
      minus(static_cast<Eigen::Index>(kIkJoints[c])) -= h;
      forward_kinematics(plus, poses);
      const double d_plus = pair_distance(poses, pair).distance_m;
      forward_kinematics(minus, poses);
      const double d_minus = pair_distance(poses, pair).distance_m;
      const double numeric = (d_plus - d_minus) / (2.0 * h);
      const double ours = rows(0, static_cast<Eigen::Index>(c)) / settings.weight;
      largest = std::max(largest, std::fabs(ours - numeric));
      EXPECT_NEAR(ours, numeric, 1e-4) << shape_link_name(pair.a) << "/" << shape_link_name(pair.b) << " joint "
                                       << kJoints[kIkJoints[c]].name;
    }
    EXPECT_NEAR(errors(0), settings.weight * settings.gain * (settings.activation_m - report.closest_distance_m), 1e-15);
    ++checked;
  }
  std::printf("%d closest pairs' rows against central differences: largest difference %.3g\n", checked, largest);
  EXPECT_GT(checked, 100);
}

// The healthy robot has one null-space direction: the waist turning while both palms hold. With the
// waist turned to 0.14 rad the torso's corners are 6.3 mm from the tracks' envelopes (both sides);
// the sub-task turns it back, the palms held, until the clearance is the activation distance.
// (The waist posture row, which does the same more slowly, is off here so the sub-task acts alone.)
TEST(ClearanceSubtask, TheTorsoTurnsAwayFromTheTracksWhileThePalmsHold) {
  JointVector start = ready_posture();
  start(static_cast<Eigen::Index>(joint_index("waist_yaw"))) = 0.14;
  LinkPoses poses;
  forward_kinematics(start, poses);
  const IkTargets hold{poses[kLeftEe], poses[kRightEe]};
  for (const bool subtask : {true, false}) {
    IkSettings settings;
    settings.waist_weight = 0.0;
    settings.self_collision_task = subtask;
    TaskPriorityIk ik(settings);
    JointVector q = start;
    JointVector next = q;
    double palm_drift = 0.0;
    bool stopped = false;
    for (int k = 0; k < 2000; ++k) {
      const Result<IkStepReport> r = ik.step(q, hold, 0, next);
      ASSERT_TRUE(r.ok());
      palm_drift = std::max({palm_drift, r.value().position_residual_m[0], r.value().position_residual_m[1]});
      stopped = stopped || r.value().self_collision.stop;
      q = next;
    }
    forward_kinematics(q, poses);
    ClearanceRows rows;
    ClearanceErrors errors;
    const SelfCollisionReport report = clearance_rows(poses, ClearanceSettings{}, rows, errors);
    const double waist = q(static_cast<Eigen::Index>(joint_index("waist_yaw")));
    std::printf("sub-task %s: waist 0.140 -> %.4f rad, %s, palms within %.2g m, no stop: %s\n", subtask ? "on " : "off",
                waist, report.close_pairs > 0 ? ("clearance " + std::to_string(report.closest_distance_m) + " m").c_str()
                                              : "no pair within the activation distance",
                palm_drift, stopped ? "no" : "yes");
    EXPECT_FALSE(stopped);
    char reason[96];
    EXPECT_STREQ(stop_reason(report, ClearanceSettings{}, reason, sizeof reason), "");
    EXPECT_LT(palm_drift, 1e-4);
    if (subtask) {
      EXPECT_LT(waist, 0.11);
      EXPECT_TRUE(report.close_pairs == 0 || report.closest_distance_m > 0.019);
    } else {
      EXPECT_GT(waist, 0.13);
    }
  }
}

struct Sweep {
  const char* name;
  JointMask cut;
  double cut_at_s;
  bool subtask;
  bool short_phases;  // the scenario's 1/1/1 s phases instead of the default 3/2.5/3 s
  double turn_rad{0.0};  // both palms' targets turned about base_link's z: the waist must turn
};

struct Outcome {
  int postures{0};
  int overlapping{0};
  std::string first_overlap;
  bool stopped{false};
  double stopped_at_s{0.0};
  std::string reason;
  double smallest_distance_m{1e9};  // of the model, over the run (the envelope for the tracks)
  double largest_waist_rad{0.0};
};

// The rescue motion, then one second more, as RcPeriod steps it (its task shape after a cut), with the
// tracks turning (left 5 rad/s, right -3 rad/s: many whole turns) and the legs sweeping -0.3 .. 2 rad
// and back every 4 s, both written into the plan every period (they are not the IK's joints).
Outcome run(const Sweep& sweep) {
  IkSettings settings;
  settings.self_collision_task = sweep.subtask;
  TaskPriorityIk ik(settings);
  JointVector q = ready_posture();
  RescueMotionConfig config;
  if (sweep.short_phases) config.phase_s = {1.0, 1.0, 1.0};
  const RescueMotion motion(q, config);
  const int periods = static_cast<int>((motion.duration_s() + 1.0) * 1000.0);
  const auto l_track = static_cast<Eigen::Index>(joint_index("l_track"));
  const auto r_track = static_cast<Eigen::Index>(joint_index("r_track"));
  const auto l_leg = static_cast<Eigen::Index>(joint_index("l_leg"));
  const auto r_leg = static_cast<Eigen::Index>(joint_index("r_leg"));
  const auto waist = static_cast<Eigen::Index>(joint_index("waist_yaw"));
  Outcome out;
  JointVector next = q;
  LinkPoses poses;
  ClearanceRows rows;
  ClearanceErrors errors;
  for (int k = 0; k < periods; ++k) {
    const double t = k * 0.001;
    const double phase = std::fmod(t, 4.0) / 2.0;  // 0 .. 2
    const double leg = -0.3 + 2.3 * (phase < 1.0 ? phase : 2.0 - phase);
    q(l_track) = 5.0 * t;
    q(r_track) = -3.0 * t;
    q(l_leg) = leg;
    q(r_leg) = leg;
    if (!out.stopped) {
      RescueSample s = motion.sample(t);
      const Matrix3 turn = Eigen::AngleAxisd(sweep.turn_rad * std::min(t, 1.0), Vector3::UnitZ()).toRotationMatrix();
      for (Pose* palm : {&s.left, &s.right}) {
        palm->p = turn * palm->p;
        palm->R = turn * palm->R;
      }
      for (Vector6* twist : {&s.left_twist, &s.right_twist}) {
        twist->head<3>() = turn * twist->head<3>();
        twist->tail<3>() = turn * twist->tail<3>();
      }
      // After a cut, the task stack the RC period uses (kin::TaskShape): the damaged arm's palm out of
      // the main task, its healthy joints and the waist held.
      const JointMask lost = t >= sweep.cut_at_s ? sweep.cut : 0;
      const TaskShape shape = task_shape_for(lost);
      IkTargets targets{s.left, s.right, s.payload_kg, shape.palm_active};
      targets.left_twist = s.left_twist;
      targets.right_twist = s.right_twist;
      const Result<IkStepReport> r = ik.step(q, targets, lost | shape.held, next);
      EXPECT_TRUE(r.ok());
      if (r.ok() && r.value().self_collision.stop) {
        out.stopped = true;  // the RC task's reaction: hold the references it sent
        out.stopped_at_s = t;
        char reason[96];
        out.reason = stop_reason(r.value().self_collision, settings.clearance, reason, sizeof reason);
      } else {
        q = next;
      }
    }
    out.largest_waist_rad = std::max(out.largest_waist_rad, std::fabs(q(waist)));
    if (k % 25 != 0) continue;
    ++out.postures;
    forward_kinematics(q, poses);
    const SelfCollisionReport report = clearance_rows(poses, ClearanceSettings{}, rows, errors);
    if (report.close_pairs > 0) out.smallest_distance_m = std::min(out.smallest_distance_m, report.closest_distance_m);
    const std::string pairs = overlapping_pairs(q);
    if (pairs.empty()) continue;
    if (out.overlapping++ == 0) out.first_overlap = "t = " + std::to_string(t) + " s: " + pairs;
  }
  return out;
}

void print(const Sweep& sweep, const Outcome& out) {
  std::printf("%-32s sub-task %-3s: %d postures, %d overlapping%s%s; %s; waist up to %.3f rad; model clearance %s\n",
              sweep.name, sweep.subtask ? "on" : "off", out.postures, out.overlapping,
              out.first_overlap.empty() ? "" : ", first ", out.first_overlap.c_str(),
              out.stopped ? ("stopped at t = " + std::to_string(out.stopped_at_s) + " s (" + out.reason + ")").c_str() : "no stop",
              out.largest_waist_rad,
              out.smallest_distance_m < 1e9 ? (std::to_string(out.smallest_distance_m) + " m").c_str() : "n/a (no pair within the activation distance)");
}

TEST(ClearanceSubtask, RescueMotionWithTurningTracksAndSweepingLegsNeverOverlaps) {
  const JointMask left_cut = joints_lost_by_link_failure_at(joint_index("l_elbow"));
  const JointMask right_cut = joints_lost_by_link_failure_at(joint_index("r_elbow"));
  const Sweep sweeps[] = {{"1/1/1 s, healthy", 0, 1e9, true, true},
                          {"1/1/1 s, l_elbow cut at 1.01 s", left_cut, 1.01, true, true},
                          {"1/1/1 s, l_elbow cut at 1.35 s", left_cut, 1.35, true, true},
                          {"1/1/1 s, l_elbow cut at 1.5 s", left_cut, 1.5, true, true},
                          {"1/1/1 s, l_elbow cut at 2.0 s", left_cut, 2.0, true, true},
                          {"1/1/1 s, r_elbow cut at 1.35 s", right_cut, 1.35, true, true},
                          {"default, healthy", 0, 1e9, true, false},
                          {"default, l_elbow cut at 1 s", left_cut, 1.0, true, false},
                          {"default, l_elbow cut at 4 s", left_cut, 4.0, true, false},
                          {"default, l_elbow cut at 7 s", left_cut, 7.0, true, false},
                          {"default, r_elbow cut at 4 s", right_cut, 4.0, true, false}};
  for (const Sweep& sweep : sweeps) {
    const Outcome out = run(sweep);
    print(sweep, out);
    EXPECT_EQ(out.overlapping, 0) << sweep.name << ": " << out.first_overlap;
    if (out.stopped) {
      EXPECT_EQ(out.reason.rfind("self-collision: ", 0), 0U) << out.reason;
    }
    EXPECT_GT(out.postures, 150);
  }
}

// The waist turned by the main task itself (both palms' targets turned by 0.3 rad about z over the
// first second: the waist's turn solves them exactly), independent of how the IK handles a cut: the
// sub-task has no null space to act in, so the stop must come; without sub-task and stop the torso
// meets the turning tracks.
TEST(ClearanceSubtask, ATurnedWaistStopsBeforeTheTurningTracksAndWithoutItMeetsThem) {
  for (const bool subtask : {true, false}) {
    const Sweep sweep{"1/1/1 s, targets turned 0.3 rad", 0, 1e9, subtask, true, 0.3};
    const Outcome out = run(sweep);
    print(sweep, out);
    if (subtask) {
      EXPECT_EQ(out.overlapping, 0) << out.first_overlap;
      EXPECT_TRUE(out.stopped);
    } else {
      EXPECT_GT(out.overlapping, 0);
    }
  }
}

}  // namespace
}  // namespace rescue::kin
