#include "core/app/bench/bench_periods.hpp"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>

#include "core/app/bench/bench_header.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/runtime/task_ports.hpp"
#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/predefined_messages.hpp"
#include "core/kinematics/rc_period.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/memory/start_up_slot.hpp"
#include "core/timing/period_recorder.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "hal/time/clock.hpp"
#include "hal/time/tsc_timer.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {

// The two measured periods: out of line, with stable names, for callgrind's --toggle-collect.
__attribute__((noinline)) drivers::JointCycleResult measured_handler_period(EthercatHandler& handler) noexcept {
  return handler.cycle();
}
__attribute__((noinline)) void measured_joint_manager_step(JointManager& manager, hal::Nanoseconds now) noexcept {
  manager.step(now);
}
// The RC task's period (kin::RcPeriod: the rescue motion at time t_s, both RC tasks), as bench fig4
// runs it; not yet wired to the handler (the RC task process is another issue's).
__attribute__((noinline)) void measured_rc_period(kin::RcPeriod& rc, double t_s) noexcept {
  (void)rc.run(t_s, 0, kin::JointVector::Zero());
}

namespace {

constexpr std::int64_t kDefaultCycles = 1000;
constexpr int kMaxCyclesToOp = 3000;
constexpr int kSettleCycles = 200;  // after "initialize robot": every joint through to Enabled

class NoEvents final : public JointEventSink {
 public:
  void on_event(const JointEvent& /*event*/) noexcept override {}
};

hal::VirtualClock g_clock{hal::kNsPerSec};
TaskLinks g_links;
PeriodRecorder g_handler;
PeriodRecorder g_manager;
PeriodRecorder g_rc;

}  // namespace

int bench_periods(const ParsedArgs& args) noexcept {
  const Result<std::int64_t> cycles = args.integer("cycles", kDefaultCycles, 1, 1'000'000);
  if (!cycles.ok()) return fail("bench", "--cycles must be 1..1000000", cycles.error());
  const Result<std::int64_t> seed = args.integer("seed", 1, 0, 1'000'000);
  if (!seed.ok()) return fail("bench", "--seed must be 0..1000000", seed.error());
  print_bench_header(stdout, "periods");

  // Init, as run_firmware wires the tasks (no threads: one thread steps both, handler first).
  drivers::RobotSegmentOptions robot_options;
  robot_options.seed = static_cast<std::uint64_t>(seed.value());
  // The robot and the bus (about 1.4 MB) from the heap at start-up, not static storage: StartUpSlot.
  static StartUpSlot<drivers::SimulatedRobot> robot_slot;
  static StartUpSlot<drivers::JointBus> bus_slot;
  if (!robot_slot.reserve() || !bus_slot.reserve()) return fail("bench", "not enough memory for the simulated robot");
  drivers::SimulatedRobot& robot = robot_slot.emplace(robot_options, g_clock.now());
  if (!robot.status().ok()) return fail("bench", "cannot build the simulated robot", robot.status().error());
  static drivers::SimulatedNic nic(robot.segment(), g_clock);
  drivers::JointBus& bus = bus_slot.emplace(nic);
  char state_dir[] = "/tmp/rescue-bench-periods-XXXXXX";
  if (mkdtemp(state_dir) == nullptr) return fail("bench", "cannot create a temporary state directory");
  static ErrorJointsFileStorage storage(state_dir);
  static TaskPorts ports(g_links);  // as `run` wires the tasks (runtime/task_ports.hpp)
  static hal::ManualWallClock wall;
  static NoEvents events;
  // The storage worker runs between the periods here (in `run` it is a thread of its own).
  static ErrorJointsStorageWorker storage_worker(ports.storage_worker_requests(), ports.storage_worker_results(), storage);
  static JointManager manager(ports.joint_manager(storage, wall, events));
  (void)manager.restore(g_clock.now());
  const Status up = bus.bring_up(ecat::MasterOptions{});
  if (!up.ok()) return fail("bench", "bring-up failed", up.error());
  static EthercatHandler handler(bus, ports.ethercat_handler(), 0);
  const hal::TscTimer timer = hal::TscTimer::calibrate();
  g_handler.configure("ethercat", 1.0 / timer.ticks_per_ns());
  g_manager.configure("joint_manager", 1.0 / timer.ticks_per_ns());
  g_rc.configure("rc", 1.0 / timer.ticks_per_ns());
  static kin::RcPeriod rc(kin::ready_posture());
  const auto motion_periods = static_cast<std::int64_t>(rc.motion().duration_s() * 1000.0);
  std::int64_t rc_k = 0;

  auto period = [&](bool record) noexcept {
    g_clock.sleep_until(bus.next_wakeup());
    // Only the measured periods go through the named functions (callgrind counts inside them).
    const std::uint64_t t0 = timer.start();
    const drivers::JointCycleResult r = record ? measured_handler_period(handler) : handler.cycle();
    const std::uint64_t t1 = timer.stop();
    handler.publish_figures(r, g_clock.now(), 0);  // untimed, as in run's loop (task_loops.cpp)
    const std::uint64_t t2 = timer.start();
    if (record) {
      measured_joint_manager_step(manager, g_clock.now());
    } else {
      manager.step(g_clock.now());
    }
    const std::uint64_t t3 = timer.stop();
    (void)storage_worker.serve_one();
    const double t_s = static_cast<double>(rc_k++ % (motion_periods > 0 ? motion_periods : 1)) * 0.001;
    const std::uint64_t t4 = timer.start();
    if (record) {
      measured_rc_period(rc, t_s);
    } else {
      (void)rc.run(t_s, 0, kin::JointVector::Zero());
    }
    const std::uint64_t t5 = timer.stop();
    if (record) {
      g_handler.record(0, t0, t1);
      g_manager.record(0, t2, t3);
      g_rc.record(0, t4, t5);
    }
    return r;
  };
  int to_op = 0;
  while (to_op < kMaxCyclesToOp && period(false).state != ecat::MasterState::op) ++to_op;
  if (to_op == kMaxCyclesToOp) return fail("bench", "the network did not reach OP");
  // Sends in order (as the message parser does) and stops at the first refusal (a side effect per
  // element, not a search).
  MessageSink<JointCommand>& parser = *ports.message_parser().joint_commands;
  for (const JointCommand& c : initialize_robot_commands(kAllJoints)) {
    // cppcheck-suppress useStlAlgorithm
    if (!parser.try_send(c)) return fail("bench", "joint handle queue full");
  }
  for (int i = 0; i < kSettleCycles; ++i) (void)period(false);
  const auto enabled = static_cast<std::size_t>(std::count_if(manager.statuses().begin(), manager.statuses().end(),
                                                              [](const JointStatus& s) { return s.state == fsm::JointState::enabled; }));

  // Measured: every joint Enabled, following its reference; nothing may allocate.
  declare_init_complete(HeapGuardMode::count);
  for (std::int64_t i = 0; i < cycles.value(); ++i) (void)period(true);
  const HeapGuardCounters heap = heap_guard_counters();

  (void)std::printf("cycles_to_op: %d cycles\n", to_op);
  (void)std::printf("joints_enabled: %zu of %zu joints\n", enabled, kJointCount);
  (void)std::printf("measured_periods: %" PRId64 " periods\n", cycles.value());
  (void)std::printf("timer_source: %s\n", hal::to_string(timer.source()));
  g_handler.execution().print(stdout, "ethercat_execution_with_sim_nic", "ns");
  g_manager.execution().print(stdout, "joint_manager_execution", "ns");
  g_rc.execution().print(stdout, "rc_execution", "ns");
  (void)std::printf("heap_allocations_after_init: %" PRIu64 " allocations\n", heap.allocations);
  (void)std::remove(state_dir);
  return heap.allocations == 0 ? 0 : fail("bench", "heap allocation after init complete");
}

}  // namespace rescue::app
