#include "core/app/bench/bench_master.hpp"

#include <algorithm>
#include <array>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/app/bench/bench_header.hpp"
#include "core/app/bench/bench_ring_break.hpp"
#include "core/app/bench/timed_nic.hpp"
#include "core/app/config/nic_option.hpp"
#include "core/app/runtime/nic_factory.hpp"
#include "core/app/runtime/sii_cache_file.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/memory/start_up_slot.hpp"
#include "core/timing/latency_histogram.hpp"
#include "drivers/cia402/cia402_enable.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "drivers/sim/segment/robot_segment.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "ecat/master/bring_up_report.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::app {
namespace {

constexpr std::int64_t kDefaultCycles = 10'000;
constexpr int kMaxCyclesToOp = 2'000;
constexpr int kColdConvergenceCycles = 5'000;

// Histograms in static storage (18 KiB each), reset (touched) before init.
LatencyHistogram g_master_ns;
LatencyHistogram g_nic_ns;
LatencyHistogram g_latch_spread_ns;
LatencyHistogram g_phase_error_ns;

// The simulated robot the master runs on (nullptr with --nic raw), and its virtual clock.
hal::VirtualClock g_virtual_clock{hal::kNsPerSec};
drivers::SimulatedSegment* g_segment = nullptr;

// Three simulated robots with different seeds: the measured run (0), the cold start (1), the
// bring-up with the SII cache warm (2). About a megabyte each of ESC memories, reserved when the
// bench starts (StartUpSlot: not in every command's image) and each built when first used.
// With --ring-nic sim each is the ring configuration and the master's two ports are a NIC pair.
constexpr std::size_t kRobots = 3;
StartUpSlot<drivers::SimulatedRobot> g_robots[kRobots];
StartUpSlot<drivers::SimulatedNic> g_robot_nics[kRobots];
StartUpSlot<drivers::SimulatedNicPair> g_robot_pairs[kRobots];
bool g_ring_robots = false;

bool reserve_robots() noexcept {
  for (std::size_t i = 0; i < kRobots; ++i) {
    if (!g_robots[i].reserve()) return false;
    if (!(g_ring_robots ? g_robot_pairs[i].reserve() : g_robot_nics[i].reserve())) return false;
  }
  return true;
}

drivers::SimulatedRobot& simulated_robot(std::uint64_t seed, std::size_t which) noexcept {
  drivers::RobotSegmentOptions options;
  options.seed = seed;
  options.max_drift_ppm = 100.0;
  options.ring = g_ring_robots;
  return g_robots[which].emplace(options, g_virtual_clock.now());
}

// The master's ports on `robot` (simulated_robot's `which`): `ring` is nullptr on the tree.
struct RobotPorts {
  hal::Nic* main{nullptr};
  hal::Nic* ring{nullptr};
};
RobotPorts robot_ports(drivers::SimulatedRobot& robot, std::size_t which) noexcept {
  drivers::SimulatedSegment& segment = robot.segment();
  g_segment = &segment;
  if (!g_ring_robots) return RobotPorts{&g_robot_nics[which].emplace(segment, g_virtual_clock), nullptr};
  drivers::SimulatedNicPair& pair = g_robot_pairs[which].emplace(segment, g_virtual_clock);
  return RobotPorts{&pair.main(), &pair.ring()};
}

// The SII cache of the bring-ups (in memory, or --sii-cache-dir's file as `run` keeps it).
ecat::SiiCache g_sii_cache;

// --sii-cache-dir DIR: the cache as `run` keeps it in its state directory (a damaged file is said
// and ignored); without it the cache is in memory only, empty at start.
void load_cache(const char* dir) noexcept {
  if (dir == nullptr) return;
  const Status loaded = load_sii_cache(dir, g_sii_cache);
  if (!loaded.ok() && loaded.error().code != Errc::not_found) {
    (void)std::printf("sii_cache: %s/%s ignored (%s)\n", dir, kSiiCacheFileName, loaded.error().what);
  }
}
void save_cache(const char* dir) noexcept {
  if (dir == nullptr || !g_sii_cache.changed()) return;
  const Status saved = save_sii_cache(dir, g_sii_cache);
  if (!saved.ok()) (void)std::printf("sii_cache: not saved to %s/%s (%s)\n", dir, kSiiCacheFileName, saved.error().what);
}

// Where bring-up time goes: each step from its start to the next one's (the last to SAFE-OP).
void print_steps(const char* prefix, const ecat::BringUpReport& report) noexcept {
  for (std::size_t i = 0; i < report.step_count; ++i) {
    const ecat::BringUpStepMark& mark = report.steps[i];
    const bool last = i + 1 == report.step_count;
    const hal::Nanoseconds end = last ? report.safe_op_at : report.steps[i + 1].at;
    const std::uint64_t frames_end = last ? report.frames : report.steps[i + 1].frames;
    (void)std::printf("%s%s: %.3f ms, %" PRIu64 " frames\n", prefix, mark.step,
                      static_cast<double>(end - mark.at) / 1e6, frames_end - mark.frames);
  }
}

// Largest |true system time - reference's system time| over all slaves, now (simulator only).
std::int64_t true_max_offset_ns() noexcept {
  std::array<std::int64_t, kSlaveCount> offsets{};
  (void)g_segment->true_clock_offsets(g_virtual_clock.now(), Span<std::int64_t>(offsets));
  std::int64_t worst = 0;
  for (const std::int64_t offset : offsets) worst = std::max(worst, std::abs(offset));
  return worst;
}

// Spread of the instants the joints latched their last outputs, when all latched the same SYNC0.
bool latch_spread_ns(std::uint64_t& spread) noexcept {
  hal::Nanoseconds first = 0;
  hal::Nanoseconds last = 0;
  std::uint64_t system_time = 0;
  bool any = false;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (kSlaves[p].kind != SlaveKind::joint_drive) continue;
    const drivers::OutputLatch latch = g_segment->esc(p).last_output_latch();
    if (latch.trigger != drivers::CycleTrigger::sync0) return false;
    if (!any) {
      first = last = latch.segment_time;
      system_time = latch.system_time;
      any = true;
    } else if (latch.system_time != system_time) {
      return false;  // not the same SYNC0 (a slave has not latched this one yet)
    }
    first = std::min(first, latch.segment_time);
    last = std::max(last, latch.segment_time);
  }
  spread = static_cast<std::uint64_t>(last - first);
  return any;
}

struct Enabler {
  drivers::JointReferences refs{};
  drivers::JointFeedback feedback{};
  bool aligned{false};
  // Holds every joint where it is and walks its drive to Operation enabled.
  void step() noexcept {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if (!aligned && (feedback.valid & joint_bit(j)) != 0) refs[j].target_position = feedback.joints[j].position_actual;
      refs[j].mode_of_operation = static_cast<std::int8_t>(kJoints[j].default_mode);
      refs[j].controlword = drivers::controlword_towards_enabled(feedback.joints[j].statusword, refs[j].controlword);
    }
    aligned = aligned || feedback.valid == kAllJoints;
  }
};

double ms(hal::Nanoseconds ns) noexcept { return static_cast<double>(ns) / 1e6; }
double us(std::uint64_t ns) noexcept { return static_cast<double>(ns) / 1e3; }

int up_to_op(drivers::JointBus& bus, hal::Clock& clock, Enabler& enabler) noexcept {
  for (int i = 0; i < kMaxCyclesToOp && bus.master().state() == ecat::MasterState::going_op; ++i) {
    clock.sleep_until(bus.next_wakeup());
    (void)bus.cycle(enabler.refs, enabler.feedback);
  }
  return bus.master().state() == ecat::MasterState::op ? 0 : 1;
}

void print_failure(ecat::Master& master) noexcept { ecat::print_bring_up_failure(stderr, "", "", master); }

// --receive-wait and --receive-spin-us (raw NIC); --scheduling normal sleeps at once, as SOEM's test
// program does. False (after saying why) on a bad value.
bool parse_receive_wait(const ParsedArgs& args, bool real_time, ReceiveWaitChoice& wait) noexcept {
  const char* text = args.value("receive-wait");
  if (text != nullptr) {
    if (std::strcmp(text, "spin") == 0) {
      wait.wait = hal::RawSocketSettings::ReceiveWait::spin;
    } else if (std::strcmp(text, "adaptive") == 0) {
      wait.wait = hal::RawSocketSettings::ReceiveWait::adaptive;
    } else if (std::strcmp(text, "sleep") == 0) {
      wait.wait = hal::RawSocketSettings::ReceiveWait::sleep;
    } else {
      (void)fail("bench", "--receive-wait must be spin, adaptive or sleep");
      return false;
    }
  }
  const Result<std::int64_t> spin_us = args.integer("receive-spin-us", kMasterReceiveSpin / 1000, 0, 1000);
  if (!spin_us.ok()) {
    (void)fail("bench", "--receive-spin-us must be 0..1000", spin_us.error());
    return false;
  }
  wait.spin = spin_us.value() * 1000;
  if (!real_time) {
    wait.wait = hal::RawSocketSettings::ReceiveWait::sleep;
    wait.spin = 0;
  }
  return true;
}

// The EtherCAT handler's real-time set-up as `run` applies it (memory locked, stack prefaulted,
// SCHED_FIFO 80 on CPU 1, timer slack 1 ns, the PM QoS request), or none (--scheduling normal).
hal::RtConfig master_rt_config(bool real_time) noexcept {
  hal::RtConfig rt;
  rt.prefault_stack_bytes = std::size_t{256} * 1024;
  rt.fifo_priority = real_time ? 80 : 0;
  rt.cpu = real_time ? 1 : -1;
  rt.timer_slack_ns = real_time ? config::kTaskTimerSlackNs : 0;
  rt.cpu_wakeup_latency_us = real_time ? config::kCpuWakeupLatencyUs : -1;
  return rt;
}

void print_scheduling(bool real_time, const ReceiveWaitChoice& wait) noexcept {
  (void)std::printf("scheduling: %s\n", real_time ? "rt (SCHED_FIFO 80, CPU 1)" : "normal (default scheduler, any CPU)");
  (void)std::printf("receive_wait: %s, spin at most %" PRId64 " us%s\n", hal::to_string(wait.wait), wait.spin / 1000,
                    wait.wait == hal::RawSocketSettings::ReceiveWait::adaptive ? ", from 20 us before the learnt round trip" : "");
}

// The cyclic run's frames that missed their deadline, and how many of them came back later (a stale
// frame in a later cycle: late, not lost); then the raw socket's receive-wait figures.
void print_receive_wait(const SelectedNic& selected, const ecat::LinkStats& before, const ecat::LinkStats& after) noexcept {
  (void)std::printf("cyclic_frames_timed_out: %" PRIu64 " frames (%" PRIu64 " came back after their deadline, %" PRIu64
                    " of them within 2 ms of their sending, the latest %.1f us after its sending, whole run)\n",
                    after.timeouts - before.timeouts, after.stale_frames - before.stale_frames,
                    after.stale_within_2ms - before.stale_within_2ms, static_cast<double>(after.stale_age_max) / 1000.0);
  const hal::RawSocketNic* raw = selected.raw();
  if (raw == nullptr) return;
  const hal::ReceiveWaitStats& w = raw->wait_stats();
  (void)std::printf("receive_wait_frames: %" PRIu64 " at once, %" PRIu64 " woke the sleep, %" PRIu64 " while spinning, %" PRIu64
                    " after the spin (whole run, bring-up included)\n",
                    w.at_once, w.while_asleep, w.while_spinning, w.after_spin);
  (void)std::printf("receive_wait_round_trip: %.2f us (learnt, adaptive only)\n", us(static_cast<std::uint64_t>(raw->expected_round_trip())));
}

// The start-up SDOs of the bring-up: the master's PDO mapping set-up, then the owner's.
void print_startup_sdos(const ecat::BringUpReport& r) noexcept {
  (void)std::printf("startup_sdos_pdo_mapping: %" PRIu32 " reads, %" PRIu32 " writes (%d drives rewritten)\n", r.pdo_reads,
                    r.pdo_writes, ecat::popcount(r.pdo_rewritten));
  (void)std::printf("startup_sdos_owner: %" PRIu32 " downloads\n", r.startup_sdos_done);
}

// The cold start's convergence: max |0x092C| after the first cycle's time distribution, the cycles
// to < 100 ns and to < 20 ns (-1: not reached), the last figure.
struct ColdFigures {
  std::uint32_t first{0};
  int under_100{-1};
  int under_20{-1};
  std::uint32_t last{0};
};

// Cycles of the cold start until every slave's |0x092C| < 20 ns (read between cycles).
void converge_cold(drivers::JointBus& bus, hal::Clock& clock, Enabler& enabler, ColdFigures& out) noexcept {
  for (int k = 0; k < kColdConvergenceCycles && out.under_20 < 0; ++k) {
    enabler.step();
    clock.sleep_until(bus.next_wakeup());
    (void)bus.cycle(enabler.refs, enabler.feedback);
    const Result<ecat::DcSnapshot> snap = bus.master().read_dc_snapshot();
    if (!snap.ok()) continue;
    out.last = snap.value().max_difference_ns;
    if (k == 0) out.first = out.last;
    if (out.under_100 < 0 && out.last < 100) out.under_100 = k + 1;
    if (out.under_20 < 0 && out.last < 20) out.under_20 = k + 1;
  }
}

// A third simulated robot of the same devices brought to OP with the SII cache as the first bring-up
// left it; its report in `out`. 0, or the bench's exit status.
int warm_bring_up(drivers::JointBus& bus, TimedNic& nic, Enabler& enabler, const ecat::MasterOptions& options,
                  std::uint64_t seed, ecat::BringUpReport& out) noexcept {
  drivers::SimulatedRobot& robot = simulated_robot(seed, 2);
  if (!robot.status().ok()) return fail("bench", "cannot build the third simulated robot", robot.status().error());
  const RobotPorts ports = robot_ports(robot, 2);
  nic.set_inner(*ports.main);
  if (ports.ring != nullptr) bus.master().use_ring(*ports.ring);
  enabler = Enabler{};
  if (!bus.bring_up(options).ok() || up_to_op(bus, nic.clock(), enabler) != 0) {
    print_failure(bus.master());
    return fail("bench", "bring-up with the SII cache warm failed");
  }
  out = bus.master().report();
  return 0;
}

void print_warm(const ecat::BringUpReport& warm) noexcept {
  (void)std::printf("bring_up_sii_cached_to_safe_op: %.3f ms\n", ms(warm.safe_op_at - warm.started_at));
  (void)std::printf("bring_up_sii_cached_to_op: %.3f ms\n", ms(warm.op_at - warm.started_at));
  (void)std::printf("bring_up_sii_cached_frames: %" PRIu64 " frames (%" PRIu32 " of %u SII images from the cache)\n",
                    warm.frames, warm.sii.cache_hits, static_cast<unsigned>(warm.slaves_counted));
  print_steps("bring_up_sii_cached_step_", warm);
}

// --dc-static-frames, --dc-target-ns and --dc-in-flight into `options`; 0, or the exit status of a
// value out of its range (said).
int parse_dc_options(const ParsedArgs& args, ecat::MasterOptions& options) noexcept {
  const ecat::MasterOptions defaults;
  const Result<std::int64_t> frames = args.integer("dc-static-frames", defaults.drift_compensation_frames, 0, 1'000'000);
  if (!frames.ok()) return fail("bench", "--dc-static-frames must be 0..1000000", frames.error());
  const Result<std::int64_t> target = args.integer("dc-target-ns", defaults.drift_compensation_target_ns, 0, 1'000'000);
  if (!target.ok()) return fail("bench", "--dc-target-ns must be 0..1000000", target.error());
  const Result<std::int64_t> in_flight =
      args.integer("dc-in-flight", defaults.drift_compensation_in_flight, 1, ecat::DatagramLink::kMaxStreamInFlight);
  if (!in_flight.ok()) return fail("bench", "--dc-in-flight must be 1..8", in_flight.error());
  options.drift_compensation_frames = static_cast<unsigned>(frames.value());
  options.drift_compensation_target_ns = static_cast<std::uint32_t>(target.value());
  options.drift_compensation_in_flight = static_cast<unsigned>(in_flight.value());
  return 0;
}

// The header, the handler's real-time set-up (each item announced), the histograms emptied.
void start_bench(bool real_time, const ReceiveWaitChoice& wait) noexcept {
  print_bench_header(stdout, "master");
  hal::apply_rt_config(master_rt_config(real_time)).print(stdout);
  print_scheduling(real_time, wait);
  g_master_ns.reset();
  g_nic_ns.reset();
  g_latch_spread_ns.reset();
  g_phase_error_ns.reset();
}

// --ring-nic (cable redundancy, docs/redundancy.md): parsed beside --nic, opened, given to the
// master; 0, or the exit status of a refusal. The ring port is not timed (nic_ns times the main
// NIC's calls only). `sim`: the benchmark's simulated robots are its own (virtual time, seeded),
// built as the ring configuration with their ring ports (robot_ports); nothing to open here.
int attach_ring(const ParsedArgs& args, const NicChoice& main, SelectedNic& selected, const ReceiveWaitChoice& wait,
                ecat::Master& master) noexcept {
  if (args.value("ring-nic") == nullptr) return 0;
  const Result<NicChoice> ring = parse_ring_nic_option(args.value("ring-nic"), main);
  if (!ring.ok()) return fail("bench", ring.error().what);
  if (ring.value().kind == NicKind::sim) return 0;
  const Status opened = selected.open_ring(ring.value(), wait);
  if (!opened.ok()) return fail_nic("bench", args.value("ring-nic"), opened.error());
  master.use_ring(*selected.ring_nic());
  return 0;
}

// Changes of the ring seen during the measured run, and the cable cut in it (--ring-cut).
std::uint64_t g_ring_changes = 0;
RingBreakRun g_ring_break;

// --ring-cut CABLE|none beside --ring-nic sim: which cable the measured run cuts (default the one
// into l_leg, position 9; 0..22 the cable into that position, 23 the ring-return cable); 0 or the
// exit status of a refusal.
int plan_ring_cut(const ParsedArgs& args, std::int64_t cycles) noexcept {
  const char* text = args.value("ring-cut");
  if (text != nullptr && !g_ring_robots) return fail("bench", "--ring-cut needs --nic sim --ring-nic sim");
  if (!g_ring_robots || (text != nullptr && std::strcmp(text, "none") == 0)) return 0;
  const Result<std::int64_t> cable = args.integer("ring-cut", 9, 0, static_cast<std::int64_t>(kSlaveCount));
  if (!cable.ok()) return fail("bench", "--ring-cut must be none or a cable 0..23 (23: the ring-return cable)", cable.error());
  g_ring_break.plan(static_cast<std::size_t>(cable.value()), cycles);
  return 0;
}
// After each measured cycle: the ring's reports drained (their count), the cable cut or restored on schedule.
std::uint64_t ring_after_cycle(ecat::Master& master, std::int64_t cycle) noexcept {
  std::uint64_t n = 0;
  ecat::RingReport report;
  while (master.pop_ring_report(report)) ++n;
  if (g_ring_robots) g_ring_break.after_cycle(cycle, *g_segment, g_virtual_clock.now());
  return n;
}

// --ring-nic sim beside --nic sim: the robots in their ring configuration (refused with raw in
// attach_ring), and the cable the measured run cuts; 0 or the exit status of a refusal.
int choose_ring_robots(const ParsedArgs& args, bool simulated, std::int64_t cycles) noexcept {
  g_ring_robots = simulated && args.value("ring-nic") != nullptr && std::strcmp(args.value("ring-nic"), "sim") == 0;
  return plan_ring_cut(args, cycles);
}

// With a ring: its state at the end, and the changes seen during the measured run.
void print_ring(const ecat::Master& master, SelectedNic& selected) noexcept {
  if (selected.ring_nic() == nullptr && !g_ring_robots) return;
  const ecat::RingStatus& rs = master.ring_status();
  (void)std::printf("ring_nic: %s\n", g_ring_robots ? "sim (the simulated robot's ring port)" : selected.ring_nic()->name());
  (void)std::printf("ring_state: %s (breaks %" PRIu64 ", repairs %" PRIu64 ", %" PRIu64 " changes in the measured run)\n",
                    ecat::to_string(rs.state), rs.breaks, rs.repairs, g_ring_changes);
  if (g_ring_robots) g_ring_break.print();
}

// What bench master's options ask for.
struct MasterBenchOptions {
  NicChoice nic{};
  std::int64_t cycles{0};
  std::int64_t seed{0};
  ecat::MasterOptions master{};
  bool simulated{false};
  bool measure_cold{false};
  const char* cache_dir{nullptr};
  bool real_time{false};
  ReceiveWaitChoice wait{};
};

// --nic, --cycles, --seed, the DC options, --ring-nic sim, --cold-start, --sii-cache-dir; 0, or the
// exit status of a refusal (said).
int parse_run_options(const ParsedArgs& args, MasterBenchOptions& o) noexcept {
  const Result<NicChoice> choice = parse_nic_option(args.value("nic"));
  if (!choice.ok()) return fail("bench", choice.error().what);
  const Result<std::int64_t> cycles = args.integer("cycles", kDefaultCycles, 100, 1'000'000);
  if (!cycles.ok()) return fail("bench", "--cycles must be 100..1000000", cycles.error());
  const Result<std::int64_t> seed = args.integer("seed", 1, 0, 1'000'000);
  if (!seed.ok()) return fail("bench", "--seed must be 0..1000000", seed.error());
  if (const int bad = parse_dc_options(args, o.master); bad != 0) return bad;
  o.nic = choice.value();
  o.cycles = cycles.value();
  o.seed = seed.value();
  o.simulated = o.nic.kind == NicKind::sim;
  if (const int bad = choose_ring_robots(args, o.simulated, o.cycles); bad != 0) return bad;
  const char* cold_start = args.value("cold-start") != nullptr ? args.value("cold-start") : "yes";
  o.measure_cold = std::strcmp(cold_start, "yes") == 0;
  if (!o.measure_cold && std::strcmp(cold_start, "no") != 0) return fail("bench", "--cold-start must be yes or no");
  o.cache_dir = args.value("sii-cache-dir");
  return 0;
}

// --scheduling and the receive wait; 0, or 1 after saying why.
int parse_scheduling_options(const ParsedArgs& args, MasterBenchOptions& o) noexcept {
  const char* scheduling = args.value("scheduling") != nullptr ? args.value("scheduling") : "rt";
  o.real_time = std::strcmp(scheduling, "rt") == 0;
  if (!o.real_time && std::strcmp(scheduling, "normal") != 0) return fail("bench", "--scheduling must be rt or normal");
  if (!parse_receive_wait(args, o.real_time, o.wait)) return 1;
  return 0;
}

// The master under test: its NIC (timed), its bus, the enable sequence, the clock it cycles on.
struct MasterRig {
  SelectedNic* selected{nullptr};
  TimedNic* nic{nullptr};
  drivers::JointBus* bus{nullptr};
  Enabler* enabler{nullptr};
  hal::Clock* clock{nullptr};
  const hal::TscTimer* timer{nullptr};
};

// Init: everything that may allocate or fault, the NIC (the simulated robot's, or --nic) and the
// ring port opened. 0, or the exit status.
int open_master(const ParsedArgs& args, const MasterBenchOptions& o, MasterRig& rig) noexcept {
  static SelectedNic selected;
  static StartUpSlot<drivers::JointBus> bus_slot;
  rig.selected = &selected;
  if (!bus_slot.reserve() || (o.simulated && !reserve_robots())) return fail("bench", "not enough memory for the simulated robots");
  hal::Nic* inner = nullptr;
  hal::Nic* sim_ring = nullptr;  // --ring-nic sim: the robot's ring port
  if (o.simulated) {
    drivers::SimulatedRobot& robot = simulated_robot(static_cast<std::uint64_t>(o.seed), 0);
    if (!robot.status().ok()) return fail("bench", "cannot build the simulated robot", robot.status().error());
    const RobotPorts ports = robot_ports(robot, 0);
    inner = ports.main;
    sim_ring = ports.ring;
  } else {
    const Status opened = selected.open(o.nic, o.wait);
    if (!opened.ok()) return fail_nic("bench", args.value("nic"), opened.error());
    inner = selected.nic();
  }
  static const hal::TscTimer timer = hal::TscTimer::calibrate();
  static TimedNic nic(*inner, timer);
  drivers::JointBus& bus = bus_slot.emplace(nic, g_ring_robots ? drivers::kRobotRingNetworkPlan : drivers::kRobotNetworkPlan);
  if (sim_ring != nullptr) bus.master().use_ring(*sim_ring);
  if (const int bad = attach_ring(args, o.nic, selected, o.wait, bus.master()); bad != 0) return bad;
  static Enabler enabler;
  rig.timer = &timer;
  rig.nic = &nic;
  rig.bus = &bus;
  rig.enabler = &enabler;
  rig.clock = &nic.clock();
  return 0;
}

// 1. Bring-up (static drift compensation as --dc-static-frames and --dc-target-ns say), then to OP.
// 0, or the exit status.
int bring_up_to_op(MasterBenchOptions& o, MasterRig& rig) noexcept {
  drivers::JointBus& bus = *rig.bus;
  o.master.sii_cache = &g_sii_cache;
  const Status up = bus.bring_up(o.master);
  if (!up.ok()) {
    print_failure(bus.master());
    return fail("bench", "bring-up failed", up.error());
  }
  if (up_to_op(bus, *rig.clock, *rig.enabler) != 0) {
    print_failure(bus.master());
    return fail("bench", "the network did not reach OP");
  }
  return 0;
}

// What the cyclic run measured besides the histograms.
struct CyclicFigures {
  std::int64_t all_valid{0};
  std::int64_t frames_lost{0};
  std::int64_t latch_samples{0};
  std::array<std::uint32_t, ecat::kLinkEventKindCount> reports_by_kind{};
  ecat::LinkStats link_before{};
  ecat::LinkStats link_after{};
  hal::PageFaults faults_at_init{};
  hal::PageFaults faults_after_run{};
  HeapGuardCounters heap_after_run{};
  Result<ecat::DcSnapshot> after_run = make_error(Errc::not_found, "not read");
  std::int64_t true_offset_after_run{-1};
};

// 2. The cyclic run, init complete: every allocation from here on is counted.
void run_cycles(const MasterBenchOptions& o, MasterRig& rig, CyclicFigures& f) noexcept {
  drivers::JointBus& bus = *rig.bus;
  Enabler& enabler = *rig.enabler;
  TimedNic& nic = *rig.nic;
  const hal::TscTimer& timer = *rig.timer;
  f.faults_at_init = hal::page_faults_of_process();
  declare_init_complete(HeapGuardMode::count);
  f.link_before = bus.master().link().stats();
  ecat::LinkReport report;
  for (std::int64_t i = 0; i < o.cycles; ++i) {
    enabler.step();
    rig.clock->sleep_until(bus.next_wakeup());
    const std::uint64_t nic_before = nic.ticks();
    const std::uint64_t t0 = timer.start();
    const drivers::JointCycleResult r = bus.cycle(enabler.refs, enabler.feedback);
    const std::uint64_t total = timer.stop() - t0;
    // cppcheck-suppress duplicateExpression ; cycle() went through the NIC: its ticks grew
    const std::uint64_t in_nic = nic.ticks() - nic_before;
    g_master_ns.record(static_cast<std::uint64_t>(timer.to_ns(total - std::min(total, in_nic))));
    g_nic_ns.record(static_cast<std::uint64_t>(timer.to_ns(in_nic)));
    g_phase_error_ns.record(static_cast<std::uint64_t>(std::abs(bus.last_cycle().dc_phase_error)));
    f.all_valid += r.valid == kAllJoints ? 1 : 0;
    f.frames_lost += r.frame_received ? 0 : 1;
    while (bus.master().pop_report(report)) ++f.reports_by_kind[static_cast<std::size_t>(report.kind) % f.reports_by_kind.size()];
    g_ring_changes += ring_after_cycle(bus.master(), i);
    std::uint64_t spread = 0;
    if (o.simulated && latch_spread_ns(spread)) {
      g_latch_spread_ns.record(spread);
      ++f.latch_samples;
    }
  }
  f.heap_after_run = heap_guard_counters();
  f.link_after = bus.master().link().stats();
  f.faults_after_run = hal::page_faults_of_process();
  f.after_run = bus.master().read_dc_snapshot();
  f.true_offset_after_run = o.simulated ? true_max_offset_ns() : -1;
}

// 3. Cold start: no static drift compensation; how many cycles until the cyclic distribution
//    brings every slave within 100 ns and 20 ns (0x092C read between cycles). 0, or the exit status.
int measure_cold_start(const MasterBenchOptions& o, MasterRig& rig, ColdFigures& cold_figures) noexcept {
  drivers::JointBus& bus = *rig.bus;
  if (o.measure_cold && o.simulated) {
    drivers::SimulatedRobot& robot = simulated_robot(static_cast<std::uint64_t>(o.seed) + 1, 1);
    if (!robot.status().ok()) return fail("bench", "cannot build the second simulated robot", robot.status().error());
    const RobotPorts ports = robot_ports(robot, 1);
    rig.nic->set_inner(*ports.main);
    if (ports.ring != nullptr) bus.master().use_ring(*ports.ring);
  }
  ecat::MasterOptions cold = o.master;
  cold.drift_compensation_frames = 0;
  cold.sii_cache = nullptr;  // read whole, as before the cache: the cold figures stay comparable
  *rig.enabler = Enabler{};
  if (o.measure_cold) {
    const Status cold_up = bus.bring_up(cold);
    if (!cold_up.ok() || up_to_op(bus, *rig.clock, *rig.enabler) != 0) {
      print_failure(bus.master());
      return fail("bench", "cold bring-up failed");
    }
    converge_cold(bus, *rig.clock, *rig.enabler, cold_figures);
  }
  return 0;
}

// The first bring-up's figures (and the warm one's, when measured).
void print_bring_up_figures(const MasterBenchOptions& o, const MasterRig& rig, const ecat::BringUpReport& first,
                            const ecat::BringUpReport* warm) noexcept {
  (void)std::printf("nic: %s\n", o.simulated ? "sim (in-process simulated robot, virtual time)" : rig.nic->name());
  (void)std::printf("time_base: %s\n", o.simulated ? "simulated (virtual clock)" : "wall (CLOCK_MONOTONIC)");
  print_ring(rig.bus->master(), *rig.selected);
  (void)std::printf("slaves: %u slaves\n", static_cast<unsigned>(first.slaves_counted));
  (void)std::printf("cycle_time: %.0f us\n", us(static_cast<std::uint64_t>(o.master.cycle_time)));
  (void)std::printf("bring_up_to_safe_op: %.3f ms\n", ms(first.safe_op_at - first.started_at));
  (void)std::printf("bring_up_to_op: %.3f ms\n", ms(first.op_at - first.started_at));
  (void)std::printf("bring_up_frames: %" PRIu64 " frames\n", first.frames);
  print_steps("bring_up_step_", first);
  print_startup_sdos(first);
  (void)std::printf("sii_frames: %" PRIu32 " frames\n", first.sii.frames);
  (void)std::printf("sii_cache_hits: %" PRIu32 " of %u slaves (%s)\n", first.sii.cache_hits,
                    static_cast<unsigned>(first.slaves_counted), o.cache_dir != nullptr ? "--sii-cache-dir" : "cache in memory, empty at start");
  if (warm != nullptr) print_warm(*warm);
}

// Distributed clocks: after the static compensation, after the cycles, the cold start, the phase, SYNC0.
void print_dc_figures(const MasterBenchOptions& o, const ecat::BringUpReport& first, std::int64_t true_offset_after_static,
                      const CyclicFigures& f, const ColdFigures& cold_figures) noexcept {
  (void)std::printf("dc_static_compensation: %u frames (at most %u, until every |0x092C| <= %u ns twice)\n",
                    first.dc_static_frames, o.master.drift_compensation_frames, o.master.drift_compensation_target_ns);
  (void)std::printf("dc_max_difference_after_static: %" PRIu32 " ns\n", first.dc_max_difference_ns);
  if (f.after_run.ok()) {
    (void)std::printf("dc_max_difference_after_cycles: %" PRIu32 " ns (after %" PRId64 " cycles)\n",
                      f.after_run.value().max_difference_ns, o.cycles);
  }
  if (o.simulated) {
    (void)std::printf("dc_true_max_offset_after_static: %" PRId64 " ns\n", true_offset_after_static);
    (void)std::printf("dc_true_max_offset_after_cycles: %" PRId64 " ns\n", f.true_offset_after_run);
  }
  if (o.measure_cold) {
    (void)std::printf("dc_cold_first_cycle_max_difference: %" PRIu32 " ns (no static compensation)\n", cold_figures.first);
    (void)std::printf("dc_cold_cycles_to_100ns: %d cycles\n", cold_figures.under_100);
    (void)std::printf("dc_cold_cycles_to_20ns: %d cycles\n", cold_figures.under_20);
    (void)std::printf("dc_cold_last_max_difference: %" PRIu32 " ns\n", cold_figures.last);
  }
  const HistogramSummary phase = g_phase_error_ns.summary();
  (void)std::printf("dc_phase_error_p99: %" PRIu64 " ns\n", phase.p99);
  (void)std::printf("dc_phase_error_max: %" PRIu64 " ns\n", phase.max);
  if (o.simulated && f.latch_samples > 0) {
    const HistogramSummary latch = g_latch_spread_ns.summary();
    (void)std::printf("sync0_latch_spread_median: %" PRIu64 " ns (%" PRId64 " SYNC0 events, 21 joints)\n", latch.p50, f.latch_samples);
    (void)std::printf("sync0_latch_spread_max: %" PRIu64 " ns\n", latch.max);
  } else {
    (void)std::printf("sync0_latch_spread_median: n/a (needs the simulator's view of the slaves)\n");
  }
}

// The cyclic run: frames, link reports, the master's CPU per cycle, the NIC, heap and page faults.
void print_cycle_figures(const MasterBenchOptions& o, const MasterRig& rig, const CyclicFigures& f,
                         const HeapGuardCounters& heap) noexcept {
  (void)std::printf("cycles: %" PRId64 " cycles\n", o.cycles);
  (void)std::printf("cycles_all_joints_valid: %" PRId64 " cycles\n", f.all_valid);
  (void)std::printf("frames_late_or_lost: %" PRId64 " frames\n", f.frames_lost);
  // A late frame's cycle is never among all_valid (nothing came back in its period): no double count.
  const auto late_but_whole = static_cast<std::int64_t>(f.link_after.stale_within_2ms_full_wkc - f.link_before.stale_within_2ms_full_wkc);
  (void)std::printf("cycles_valid_within_2ms: %" PRId64 " cycles (as SOEM's test counts: the frame back within 2 ms of its sending, "
                    "EC_TIMEOUTRET, with its full working counter, whatever the period; %" PRId64 " of them back after their period)\n",
                    std::min(f.all_valid + late_but_whole, o.cycles), late_but_whole);
  (void)std::printf("link_reports: %" PRIu32 " lost, %" PRIu32 " not operational, %" PRIu32 " restored, %" PRIu32
                    " silent\n",
                    f.reports_by_kind[0], f.reports_by_kind[1], f.reports_by_kind[2],
                    f.reports_by_kind[static_cast<std::size_t>(ecat::LinkEventKind::silent)]);
  const HistogramSummary master = g_master_ns.summary();
  (void)std::printf("timer_source: %s\n", hal::to_string(rig.timer->source()));
  (void)std::printf("master_cycle_cpu_median: %.2f us\n", us(master.p50));
  (void)std::printf("master_cycle_cpu_p99: %.2f us\n", us(master.p99));
  (void)std::printf("master_cycle_cpu_max: %.2f us\n", us(master.max));
  const HistogramSummary wire = g_nic_ns.summary();
  (void)std::printf("nic_time_median: %.2f us (%s)\n", us(wire.p50), o.simulated ? "the simulator processing the frame" : "send + wait for the frame");
  print_receive_wait(*rig.selected, f.link_before, f.link_after);
  (void)std::printf("heap_guard_covers_malloc: %s\n", heap_guard_covers_malloc() ? "yes" : "no (sanitizer build)");
  (void)std::printf("heap_allocations_after_init: %" PRIu64 " allocations (cyclic run %" PRIu64 ")\n", heap.allocations,
                    f.heap_after_run.allocations);
  (void)std::printf("page_faults_after_init: %" PRIu64 " faults (cyclic run)\n",
                    (f.faults_after_run.minor - f.faults_at_init.minor) + (f.faults_after_run.major - f.faults_at_init.major));
}

}  // namespace

int bench_master(const ParsedArgs& args) noexcept {
  MasterBenchOptions o;
  if (const int bad = parse_run_options(args, o); bad != 0) return bad;
  load_cache(o.cache_dir);
  if (const int bad = parse_scheduling_options(args, o); bad != 0) return bad;

  // Init: everything that may allocate or fault. The handler's real-time set-up (docs/hal.md), each
  // item announced; --scheduling normal (comparisons, docs/master.md): as SOEM's test program runs.
  start_bench(o.real_time, o.wait);
  MasterRig rig;
  if (const int bad = open_master(args, o, rig); bad != 0) return bad;
  if (const int bad = bring_up_to_op(o, rig); bad != 0) return bad;
  const ecat::BringUpReport first = rig.bus->master().report();
  const std::int64_t true_offset_after_static = o.simulated ? true_max_offset_ns() : -1;

  CyclicFigures cyclic;
  run_cycles(o, rig, cyclic);
  ColdFigures cold_figures;
  if (const int bad = measure_cold_start(o, rig, cold_figures); bad != 0) return bad;
  // 4. On the simulated robot: the bring-up of another robot of the same devices with the SII cache
  //    warm (what `run` does from its second start on), the default static compensation.
  ecat::BringUpReport warm{};
  const bool warm_measured = o.measure_cold && o.simulated;
  if (warm_measured && warm_bring_up(*rig.bus, *rig.nic, *rig.enabler, o.master, static_cast<std::uint64_t>(o.seed) + 2, warm) != 0) return 1;
  const HeapGuardCounters heap = heap_guard_counters();

  print_bring_up_figures(o, rig, first, warm_measured ? &warm : nullptr);
  print_dc_figures(o, first, true_offset_after_static, cyclic, cold_figures);
  print_cycle_figures(o, rig, cyclic, heap);
  save_cache(o.cache_dir);
  return heap.allocations == 0 ? 0 : fail("bench", "heap allocation after init complete");
}

}  // namespace rescue::app
