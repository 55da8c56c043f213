#include "core/app/bench/bench_sim.hpp"
#include "drivers/joint/joint_units.hpp"

#include <algorithm>
#include <array>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>

#include "core/app/bench/bench_header.hpp"
#include "core/app/bench/timed_nic.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/memory/start_up_slot.hpp"
#include "core/timing/latency_histogram.hpp"
#include "drivers/cia402/cia402_enable.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::app {
namespace {

constexpr std::int64_t kDefaultCycles = 60'000;
constexpr int kMaxCyclesToEnabled = 500;
constexpr double kSecondsPerHour = 3600.0;

enum class Motion : std::uint8_t { hold, move };

// Histograms in static storage (18 KiB each), reset before each run.
LatencyHistogram g_cycle_ns;
LatencyHistogram g_segment_ns;
hal::VirtualClock g_clock{hal::kNsPerSec};

// One simulated robot per run and the bus that drives them: about a megabyte each of ESC memories,
// reserved when the bench starts (StartUpSlot: not in every command's image), built when first used.
StartUpSlot<drivers::SimulatedRobot> g_hold_robot;
StartUpSlot<drivers::SimulatedRobot> g_move_robot;
StartUpSlot<drivers::JointBus> g_bus;

bool reserve_robots() noexcept { return g_hold_robot.reserve() && g_move_robot.reserve() && g_bus.reserve(); }

drivers::SimulatedRobot& robot_for(Motion motion, std::uint64_t seed) noexcept {
  drivers::RobotSegmentOptions options;
  options.seed = seed;
  options.max_drift_ppm = 100.0;
  return (motion == Motion::hold ? g_hold_robot : g_move_robot).emplace(options, g_clock.now());
}

// The references of every joint: enabled through CiA 402, then held at the position it had, or
// moving around it (CSP: triangles up to 0.4 rad; CSV: speed waves up to 1 rad/s).
struct Exerciser {
  drivers::JointReferences refs{};
  drivers::JointFeedback feedback{};
  std::array<std::int32_t, kJointCount> start{};
  bool aligned{false};

  void step(Motion motion, std::int64_t k) noexcept {
    if (!aligned && feedback.valid == kAllJoints) {
      for (std::size_t j = 0; j < kJointCount; ++j) start[j] = feedback.joints[j].position_actual;
      aligned = true;
    }
    const auto phase = static_cast<int>(k % 4000);
    const int triangle = phase < 2000 ? phase : 4000 - phase;  // 0..2000
    for (std::size_t j = 0; j < kJointCount; ++j) {
      drivers::JointOutputs& r = refs[j];
      r.mode_of_operation = static_cast<std::int8_t>(kJoints[j].default_mode);
      r.controlword = drivers::controlword_towards_enabled(feedback.joints[j].statusword, r.controlword);
      const bool moving = motion == Motion::move && aligned;
      r.target_position = start[j] + (moving ? drivers::rad_to_counts(0.0002 * triangle) : 0);
      r.target_velocity = moving ? drivers::rad_to_counts(0.001 * (triangle - 1000)) : 0;
    }
  }
  bool all_enabled() const noexcept {
    return feedback.valid == kAllJoints &&
           std::all_of(feedback.joints.begin(), feedback.joints.end(),
                       [](const drivers::JointInputs& in) { return drivers::is_enabled(in.statusword); });
  }
};

struct RunFigures {
  HistogramSummary cycle{};
  HistogramSummary segment{};
  std::uint64_t host_ns{0};
  std::uint64_t cpu_ns{0};
  std::int64_t cycles{0};
  std::int64_t all_valid{0};
  std::uint64_t frames{0};  // through the segment during the run
};

// CPU time of this thread: unlike the wall clock, not stretched when other work shares the CPU.
std::uint64_t thread_cpu_ns() noexcept {
  timespec ts{};
  if (::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return 0;
  return static_cast<std::uint64_t>(ts.tv_sec) * 1'000'000'000ULL + static_cast<std::uint64_t>(ts.tv_nsec);
}

const char* name_of(Motion m) noexcept { return m == Motion::hold ? "hold" : "move"; }

int run(Motion motion, std::uint64_t seed, std::int64_t cycles, const hal::TscTimer& timer, RunFigures& out) noexcept {
  drivers::SimulatedRobot& robot = robot_for(motion, seed);
  if (!robot.status().ok()) return fail("bench", "cannot build the simulated robot", robot.status().error());
  // The NICs and the bus are built once, at the first run, and re-pointed at each robot.
  static drivers::SimulatedNic hold_nic(robot_for(Motion::hold, seed).segment(), g_clock);
  static drivers::SimulatedNic move_nic(robot_for(Motion::move, seed).segment(), g_clock);
  static TimedNic nic(hold_nic, timer);
  drivers::JointBus& bus = g_bus.emplace(nic);
  static Exerciser exerciser;
  nic.set_inner(motion == Motion::hold ? hold_nic : move_nic);
  exerciser = Exerciser{};

  ecat::MasterOptions options;
  options.drift_compensation_frames = 2000;  // converged enough; the speed is what is measured
  if (!bus.bring_up(options).ok()) return fail("bench", "bring-up failed");
  for (int i = 0; i < kMaxCyclesToEnabled && !(bus.master().state() == ecat::MasterState::op && exerciser.all_enabled()); ++i) {
    exerciser.step(motion, 0);
    g_clock.sleep_until(bus.next_wakeup());
    (void)bus.cycle(exerciser.refs, exerciser.feedback);
  }
  if (!exerciser.all_enabled()) return fail("bench", "the joints were not enabled");

  g_cycle_ns.reset();
  g_segment_ns.reset();
  const std::uint64_t frames_before = robot.segment().counters().frames;
  const std::uint64_t cpu_start = thread_cpu_ns();
  const std::uint64_t run_start = timer.start();
  for (std::int64_t k = 0; k < cycles; ++k) {
    exerciser.step(motion, k);
    g_clock.sleep_until(bus.next_wakeup());
    const std::uint64_t in_nic_before = nic.ticks();
    const std::uint64_t t0 = timer.start();
    const drivers::JointCycleResult r = bus.cycle(exerciser.refs, exerciser.feedback);
    const std::uint64_t total = timer.stop() - t0;
    g_cycle_ns.record(static_cast<std::uint64_t>(timer.to_ns(total)));
    // cppcheck-suppress duplicateExpression ; cycle() went through the NIC: its ticks grew
    g_segment_ns.record(static_cast<std::uint64_t>(timer.to_ns(nic.ticks() - in_nic_before)));
    out.all_valid += r.valid == kAllJoints ? 1 : 0;
  }
  out.host_ns = static_cast<std::uint64_t>(timer.to_ns(timer.stop() - run_start));
  out.cpu_ns = thread_cpu_ns() - cpu_start;
  out.frames = robot.segment().counters().frames - frames_before;
  out.cycles = cycles;
  out.cycle = g_cycle_ns.summary();
  out.segment = g_segment_ns.summary();
  return 0;
}

void print(Motion motion, const RunFigures& f) noexcept {
  const char* m = name_of(motion);
  const double simulated_s = static_cast<double>(f.cycles) * 1e-3;
  const double wall_ratio = f.host_ns > 0 ? simulated_s / (static_cast<double>(f.host_ns) * 1e-9) : 0.0;
  const double cpu_ratio = f.cpu_ns > 0 ? simulated_s / (static_cast<double>(f.cpu_ns) * 1e-9) : 0.0;
  (void)std::printf("%s_cycles_all_joints_valid: %" PRId64 " cycles (of %" PRId64 ")\n", m, f.all_valid, f.cycles);
  (void)std::printf("%s_frames_per_cycle: %.2f frames\n", m, static_cast<double>(f.frames) / static_cast<double>(f.cycles));
  (void)std::printf("%s_robot_cycle_host_median: %" PRIu64 " ns (master + simulator, per simulated 1 ms cycle)\n", m, f.cycle.p50);
  (void)std::printf("%s_robot_cycle_host_p99: %" PRIu64 " ns\n", m, f.cycle.p99);
  (void)std::printf("%s_segment_cycle_host_median: %" PRIu64 " ns (the simulator alone)\n", m, f.segment.p50);
  (void)std::printf("%s_segment_cycle_host_p99: %" PRIu64 " ns\n", m, f.segment.p99);
  (void)std::printf("%s_simulated_seconds_per_host_second: %.0f s/s (wall clock)\n", m, wall_ratio);
  (void)std::printf("%s_simulated_seconds_per_cpu_second: %.0f s/s (this thread's CPU time)\n", m, cpu_ratio);
  (void)std::printf("%s_host_seconds_per_simulated_hour: %.1f s (wall clock)\n", m, wall_ratio > 0.0 ? kSecondsPerHour / wall_ratio : 0.0);
  (void)std::printf("%s_cpu_seconds_per_simulated_hour: %.1f s\n", m, cpu_ratio > 0.0 ? kSecondsPerHour / cpu_ratio : 0.0);
}

}  // namespace

int bench_sim(const ParsedArgs& args) noexcept {
  const Result<std::int64_t> cycles = args.integer("cycles", kDefaultCycles, 100, 3'600'000);
  if (!cycles.ok()) return fail("bench", "--cycles must be 100..3600000", cycles.error());
  const Result<std::int64_t> seed = args.integer("seed", 1, 0, 1'000'000);
  if (!seed.ok()) return fail("bench", "--seed must be 0..1000000", seed.error());

  print_bench_header(stdout, "sim");
  // Memory locked and pinned to one CPU so the figures do not include page faults or migrations;
  // the default scheduler (a run of many seconds at SCHED_FIFO would starve the machine).
  hal::RtConfig rt;
  rt.prefault_stack_bytes = std::size_t{256} * 1024;
  rt.cpu = 1;
  hal::apply_rt_config(rt).print(stdout);
  static const hal::TscTimer timer = hal::TscTimer::calibrate();
  (void)std::printf("timer_source: %s\n", hal::to_string(timer.source()));
  (void)std::printf("robot_slaves: %u slaves (2 junctions, 21 joint drives), 1 ms cycle, virtual time\n", static_cast<unsigned>(kSlaveCount));

  const char* motion = args.value("motion");
  const bool both = motion == nullptr || std::strcmp(motion, "both") == 0;
  const bool hold_only = motion != nullptr && std::strcmp(motion, "hold") == 0;
  const bool move_only = motion != nullptr && std::strcmp(motion, "move") == 0;
  if (!both && !hold_only && !move_only) return fail("bench", "--motion must be hold, move or both");

  RunFigures hold{};
  RunFigures move{};
  if (!reserve_robots()) return fail("bench", "not enough memory for the simulated robots");
  declare_init_complete(HeapGuardMode::count);
  const auto s = static_cast<std::uint64_t>(seed.value());
  if (!move_only) {
    if (run(Motion::hold, s, cycles.value(), timer, hold) != 0) return 1;
    print(Motion::hold, hold);
  }
  if (!hold_only) {
    if (run(Motion::move, s, cycles.value(), timer, move) != 0) return 1;
    print(Motion::move, move);
  }
  const HeapGuardCounters heap = heap_guard_counters();
  (void)std::printf("heap_allocations_after_init: %" PRIu64 " allocations\n", heap.allocations);
  return heap.allocations == 0 ? 0 : fail("bench", "heap allocation after init complete");
}

}  // namespace rescue::app
