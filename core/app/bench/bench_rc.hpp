// `rescue-motion bench rc`: what the RC tasks' kinematics cost per period on this machine. After
// init (TSC calibration, random configurations, solvers constructed) it measures, per call:
//   rc_fk_arm       FK of one 7-joint arm chain (waist to left palm)
//   rc_jacobian_arm its geometric Jacobian (with the FK it needs)
//   rc_dls_arm      one damped least-squares velocity IK step of that chain (Jacobian included)
//   rc_fk_all       FK of every link of the robot
//   rc_ik_step      one task-priority IK step: both palms, forearms level, COM (FK, Jacobians included)
//   rc_period       the whole RC period: trajectory sample, IK step, teleoperation task
// each as median, p99 and max (ns), and the heap allocations after init (must be 0).
//
// The comparison with Orocos KDL runs in the same process and run when a RcComparison is given:
// rescue-motion (firmware) never links KDL, so it prints its own figures only; the non-firmware
// program rescue-bench-rc-kdl (tests/core/kinematics) runs this same function with KDL's
// ChainFkSolverPos_recursive, ChainJntToJacSolver and ChainIkSolverVel_wdls on the same chain
// and prints the ratios (docs/kinematics.md).
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

// Another library's kernels on the same 7-joint chain; each call uses q (7 values) and, for the
// velocity IK, a twist (6 values), and must keep its result observable (e.g. in the context).
struct RcComparison {
  const char* name;  // printed as the key prefix, e.g. "kdl"
  void* context;
  void (*fk)(void* context, const double* q);
  void (*jacobian)(void* context, const double* q);
  void (*velocity_ik)(void* context, const double* q, const double* twist);
};

int run_bench_rc(const ParsedArgs& args, const RcComparison* comparison) noexcept;
int bench_rc(const ParsedArgs& args) noexcept;  // run_bench_rc(args, nullptr)

}  // namespace rescue::app
