// rescue-bench-rc-kdl: `bench rc` with Orocos KDL on the same 7-joint chain in the same run, so
// the ratios compare like with like (same process, machine state, configurations and timer).
// Not firmware: it exists because rescue-motion must never link KDL (docs/kinematics.md).
//   rescue-bench-rc-kdl [--periods N]
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolvervel_wdls.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "core/app/bench/bench_rc.hpp"
#include "core/app/cli/commands.hpp"
#include "tests/core/kinematics/kdl_chain.hpp"

namespace {

using namespace rescue;

struct KdlKernels {
  KDL::Chain chain;
  KDL::ChainFkSolverPos_recursive fk;
  KDL::ChainJntToJacSolver jac;
  KDL::ChainIkSolverVel_wdls wdls;
  KDL::JntArray q{kin::kArmJoints};
  KDL::JntArray qdot{kin::kArmJoints};
  KDL::Frame frame;
  KDL::Jacobian jacobian{kin::kArmJoints};
  double sink{0.0};

  explicit KdlKernels(const KDL::Chain& c) : chain(c), fk(chain), jac(chain), wdls(chain) {
    wdls.setLambda(0.06);  // damping of the same order as ours; KDL's wdls always does a full SVD
  }
  void load(const double* values) {
    for (unsigned i = 0; i < static_cast<unsigned>(kin::kArmJoints); ++i) q(i) = values[i];
  }
};

void kdl_fk(void* context, const double* q) {
  auto& k = *static_cast<KdlKernels*>(context);
  k.load(q);
  (void)k.fk.JntToCart(k.q, k.frame);
  k.sink += k.frame.p.x();
}

void kdl_jacobian(void* context, const double* q) {
  auto& k = *static_cast<KdlKernels*>(context);
  k.load(q);
  (void)k.jac.JntToJac(k.q, k.jacobian);
  k.sink += k.jacobian(0, 3);
}

void kdl_velocity_ik(void* context, const double* q, const double* twist) {
  auto& k = *static_cast<KdlKernels*>(context);
  k.load(q);
  const KDL::Twist t(KDL::Vector(twist[0], twist[1], twist[2]), KDL::Vector(twist[3], twist[4], twist[5]));
  (void)k.wdls.CartToJnt(k.q, t, k.qdot);
  k.sink += k.qdot(2);
}

}  // namespace

int main(int argc, char** argv) {
  // Same options as `rescue-motion bench rc`.
  const char* args[16] = {"rc"};
  int count = 1;
  for (int i = 1; i < argc && count < 16; ++i) args[count++] = argv[i];
  auto parsed = app::parse_args(app::kBenchCommand, count, args);
  if (!parsed.ok()) return app::fail("rescue-bench-rc-kdl", "options", parsed.error());
  if (parsed.value().help_requested()) {
    std::printf(
        "usage: rescue-bench-rc-kdl [--periods N]\n\n"
        "`rescue-motion bench rc` (the RC tasks' kinematics: FK, Jacobian and DLS of the 7-joint left arm,\n"
        "FK of all links, the task-priority IK step, the whole RC period; median / p99 / max in ns) plus\n"
        "Orocos KDL's ChainFkSolverPos_recursive, ChainJntToJacSolver and ChainIkSolverVel_wdls on the same\n"
        "chain and configurations in the same process, with the ratios KDL / ours (docs/kinematics.md).\n"
        "Not firmware and never installed: rescue-motion does not link KDL.\n\n"
        "  --periods N   samples per kernel (as `rescue-motion bench rc`)\n"
        "  --help        this text\n");
    return 0;
  }
  static KdlKernels kernels(kin::test::make_kdl_chain(kin::kLeftArm));
  const app::RcComparison kdl{"kdl", &kernels, kdl_fk, kdl_jacobian, kdl_velocity_ik};
  const int status = app::run_bench_rc(parsed.value(), &kdl);
  std::printf("kdl_checksum: %.3f rad\n", kernels.sink);
  return status;
}
