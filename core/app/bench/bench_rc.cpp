#include "core/app/bench/bench_rc.hpp"

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "core/app/bench/bench_header.hpp"
#include "core/app/config/firmware_config.hpp"
#include "core/app/config/task_table.hpp"
#include "core/kinematics/damped_least_squares.hpp"
#include "core/kinematics/rc_period.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/timing/latency_histogram.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::app {
namespace {

using kin::ArmVector;
using kin::JointVector;

constexpr std::size_t kConfigs = 1024;  // power of two: index with a mask
constexpr int kBatch = 8;                // kernel calls per timing (amortises the timer's cost)

// Static: touched before init, never allocated afterwards.
ArmVector g_arm_q[kConfigs];
double g_arm_raw[kConfigs][kin::kArmJoints];
double g_twist[6] = {0.01, -0.02, 0.015, 0.05, -0.03, 0.02};
JointVector g_all_q[kConfigs];
LatencyHistogram g_hist[9];
volatile double g_sink = 0.0;

double uniform(std::uint64_t& state, double lo, double hi) noexcept {
  state = state * 6364136223846793005ULL + 1442695040888963407ULL;
  return lo + (hi - lo) * static_cast<double>(state >> 11U) * (1.0 / 9007199254740992.0);
}

void make_configurations() noexcept {
  std::uint64_t state = 1;
  for (std::size_t n = 0; n < kConfigs; ++n) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const JointLimits& lim = kJoints[j].limits;
      g_all_q[n](static_cast<Eigen::Index>(j)) =
          kJoints[j].continuous ? uniform(state, -3.0, 3.0) : uniform(state, lim.position_min_rad, lim.position_max_rad);
    }
    g_arm_q[n] = kin::chain_joint_values(kin::kLeftArm, g_all_q[n]);
    for (int i = 0; i < kin::kArmJoints; ++i) g_arm_raw[n][i] = g_arm_q[n](i);
  }
}

// Times `samples` batches of kBatch calls of `call(config index)`; records ns per call.
template <typename Call>
void measure(const hal::TscTimer& timer, LatencyHistogram& hist, std::int64_t samples, Call&& call) noexcept {
  std::size_t next = 0;
  for (std::int64_t s = 0; s < samples; ++s) {
    const std::uint64_t start = timer.start();
    for (int b = 0; b < kBatch; ++b) call((next++) & (kConfigs - 1));
    const std::int64_t ns = timer.to_ns(timer.stop() - start);
    hist.record(static_cast<std::uint64_t>((ns + kBatch / 2) / kBatch));
  }
}

void print_figure(const char* key, const LatencyHistogram& hist) noexcept {
  (void)std::printf("%s_median: %" PRIu64 " ns\n", key, hist.percentile(50.0));
  (void)std::printf("%s_p99: %" PRIu64 " ns\n", key, hist.percentile(99.0));
  (void)std::printf("%s_max: %" PRIu64 " ns\n", key, hist.max());
}

void print_ratio(const char* prefix, const char* kernel, const LatencyHistogram& theirs,
                 const LatencyHistogram& ours) noexcept {
  const auto ratio = [](std::uint64_t a, std::uint64_t b) {
    return b == 0 ? 0.0 : static_cast<double>(a) / static_cast<double>(b);
  };
  (void)std::printf("%s_%s_ratio_median: %.2f x\n", prefix, kernel, ratio(theirs.percentile(50.0), ours.percentile(50.0)));
  (void)std::printf("%s_%s_ratio_p99: %.2f x\n", prefix, kernel, ratio(theirs.percentile(99.0), ours.percentile(99.0)));
}

}  // namespace

int run_bench_rc(const ParsedArgs& args, const RcComparison* comparison) noexcept {
  const Result<std::int64_t> samples = args.integer("periods", 20000, 100, 10'000'000);
  if (!samples.ok()) return fail("bench", "--periods", samples.error());

  // ---- init: everything that may allocate or fault ----
  print_bench_header(stdout, "rc");
  // As the RC task runs (Table I: SCHED_FIFO 65 on its CPU): without it, on a loaded machine the
  // other processes' preemptions, not the kernels, make the p99 of a 100 ns kernel. The comparison
  // library is measured in the same process, so under the same settings. Refused without privileges
  // (printed below); the figures are then those of a normal process.
  hal::RtConfig rt;
  rt.prefault_stack_bytes = std::size_t{256} * 1024;
  rt.fifo_priority = config::kRcTaskPriority;
  rt.cpu = table_cpu_on_this_machine(config::kRcTaskCpu);
  const hal::RtReport report = hal::apply_rt_config(rt);
  report.print(stdout);
  const hal::TscTimer timer = hal::TscTimer::calibrate();
  make_configurations();
  for (LatencyHistogram& h : g_hist) h.reset();
  static kin::RcPeriod rc(kin::ready_posture());
  static kin::TaskPriorityIk ik;
  static kin::LinkPoses poses;
  const kin::JointVector teleop_velocity = kin::JointVector::Zero();
  // IK targets near the configurations: a few mm and mrad off, as within a tracked trajectory.
  static kin::IkTargets targets[kConfigs];
  for (std::size_t n = 0; n < kConfigs; ++n) {
    kin::forward_kinematics(g_all_q[n], poses);
    targets[n] = kin::IkTargets{poses[kin::kLeftEe], poses[kin::kRightEe], 35.0};
    targets[n].left.p += kin::Vector3(0.002, -0.001, 0.003);
    targets[n].right.p += kin::Vector3(-0.001, 0.002, 0.001);
  }
  (void)std::fflush(stdout);
  declare_init_complete(HeapGuardMode::count);

  // ---- measured: ours ----
  measure(timer, g_hist[0], samples.value(), [](std::size_t i) {
    g_sink = g_sink + kin::chain_tip_pose(kin::kLeftArm, g_arm_q[i]).p.x();
  });
  measure(timer, g_hist[1], samples.value(), [](std::size_t i) {
    kin::ArmJacobian j;
    kin::Pose tip;
    kin::chain_jacobian(kin::kLeftArm, g_arm_q[i], j, tip);
    g_sink = g_sink + j(0, 3);
  });
  measure(timer, g_hist[2], samples.value(), [](std::size_t i) {
    kin::ArmVector qdot;
    const kin::Vector6 twist = Eigen::Map<const kin::Vector6>(g_twist);
    (void)kin::arm_velocity_ik(kin::kLeftArm, g_arm_q[i], twist, qdot);
    g_sink = g_sink + qdot(2);
  });
  measure(timer, g_hist[3], samples.value(), [](std::size_t i) {
    kin::forward_kinematics(g_all_q[i], poses);
    g_sink = g_sink + poses[kin::kRightEe].p.y();
  });
  std::uint64_t ik_failures = 0;
  // Whole IK step and RC period: timed one call each (microseconds; the timer's cost is negligible).
  for (std::int64_t s = 0; s < samples.value(); ++s) {
    const std::size_t i = static_cast<std::size_t>(s) & (kConfigs - 1);
    kin::JointVector next;
    const std::uint64_t start = timer.start();
    const Result<kin::IkStepReport> r = ik.step(g_all_q[i], targets[i], 0, next);
    g_hist[4].record(static_cast<std::uint64_t>(timer.to_ns(timer.stop() - start)));
    if (!r.ok()) ++ik_failures;
    g_sink = g_sink + next(4);
  }
  const double period_s = rc.motion().duration_s();
  for (std::int64_t s = 0; s < samples.value(); ++s) {
    const double t = static_cast<double>(s % static_cast<std::int64_t>(period_s * 1000.0)) * 0.001;
    const std::uint64_t start = timer.start();
    const Result<kin::IkStepReport> r = rc.run(t, 0, teleop_velocity);
    g_hist[5].record(static_cast<std::uint64_t>(timer.to_ns(timer.stop() - start)));
    if (!r.ok()) ++ik_failures;
  }
  const HeapGuardCounters heap = heap_guard_counters();

  // ---- measured: the comparison library on the same chain and configurations ----
  HeapGuardCounters heap_other{};
  if (comparison != nullptr) {
    const RcComparison& c = *comparison;
    measure(timer, g_hist[6], samples.value(), [&c](std::size_t i) { c.fk(c.context, g_arm_raw[i]); });
    measure(timer, g_hist[7], samples.value(), [&c](std::size_t i) { c.jacobian(c.context, g_arm_raw[i]); });
    measure(timer, g_hist[8], samples.value(),
            [&c](std::size_t i) { c.velocity_ik(c.context, g_arm_raw[i], g_twist); });
    const HeapGuardCounters after = heap_guard_counters();
    heap_other.allocations = after.allocations - heap.allocations;
  }

  // ---- report ----
  (void)std::printf("timer_source: %s\n", hal::to_string(timer.source()));
  (void)std::printf("chain: waist_yaw + 6 left-arm joints to l_ee (7 joints), %zu random configurations\n", kConfigs);
  (void)std::printf("samples: %" PRId64 " samples\n", samples.value());
  (void)std::printf("kernel_batch: %d calls\n", kBatch);
  print_figure("rc_fk_arm", g_hist[0]);
  print_figure("rc_jacobian_arm", g_hist[1]);
  print_figure("rc_dls_arm", g_hist[2]);
  print_figure("rc_fk_all", g_hist[3]);
  print_figure("rc_ik_step", g_hist[4]);
  print_figure("rc_period", g_hist[5]);
  (void)std::printf("rc_period_target_p99: 10000 ns\n");
  (void)std::printf("ik_failures: %" PRIu64 " steps\n", ik_failures);
  (void)std::printf("heap_guard_covers_malloc: %s\n", heap_guard_covers_malloc() ? "yes" : "no (sanitizer build)");
  (void)std::printf("heap_allocations_after_init: %" PRIu64 " allocations\n", heap.allocations);
  if (comparison == nullptr) {
    (void)std::printf("comparison: none in the firmware binary; rescue-bench-rc-kdl runs this bench with Orocos KDL\n");
  } else {
    char key[64];
    (void)std::snprintf(key, sizeof key, "%s_fk_arm", comparison->name);
    print_figure(key, g_hist[6]);
    (void)std::snprintf(key, sizeof key, "%s_jacobian_arm", comparison->name);
    print_figure(key, g_hist[7]);
    (void)std::snprintf(key, sizeof key, "%s_wdls_arm", comparison->name);
    print_figure(key, g_hist[8]);
    print_ratio(comparison->name, "fk", g_hist[6], g_hist[0]);
    print_ratio(comparison->name, "jacobian", g_hist[7], g_hist[1]);
    print_ratio(comparison->name, "dls", g_hist[8], g_hist[2]);
    (void)std::printf("%s_heap_allocations: %" PRIu64 " allocations\n", comparison->name, heap_other.allocations);
  }
  (void)std::printf("checksum: %.3f rad\n", static_cast<double>(g_sink));
  return heap.allocations == 0 && ik_failures == 0 ? 0 : fail("bench", "heap allocation or IK failure after init");
}

int bench_rc(const ParsedArgs& args) noexcept { return run_bench_rc(args, nullptr); }

}  // namespace rescue::app
