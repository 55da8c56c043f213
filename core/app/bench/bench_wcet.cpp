#include "core/app/bench/bench_wcet.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/app/bench/bench_files.hpp"
#include "core/app/bench/bench_header.hpp"
#include "core/app/bench/wcet_budget.hpp"
#include "core/app/bench/wcet_conditions.hpp"
#include "core/app/bench/wcet_operator_load.hpp"
#include "core/app/tasks/period_mark.hpp"
#include "core/app/bench/rt_duty_rest.hpp"
#include "core/app/bench/wcet_scenarios.hpp"
#include "core/app/config/firmware_config.hpp"
#include "core/app/config/task_table.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/runtime/task_ports.hpp"
#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/message_parser.hpp"
#include "core/app/tasks/predefined_messages.hpp"
#include "core/kinematics/rc_period.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/memory/start_up_slot.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "drivers/sim/segment/simulated_nic.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "ecat/capture/capture_queue.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "ecat/mailbox/mailbox_client.hpp"
#include "ecat/master/link_diagnostics.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/clock.hpp"
#include "hal/time/tsc_timer.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {
namespace {

constexpr std::int64_t kDefaultPeriods = 20000;
constexpr std::int64_t kShortPeriods = 2500;  // 50 blocks of 50: just above the method's 40
constexpr std::int64_t kMaxPeriods = 200000;
constexpr int kMaxCyclesToOp = 3000;
constexpr int kSettleCycles = 200;
// The next power cycle of every slave comes once every joint is Enabled again, after a hold at
// random in [0, kHoldSpread) periods (so the heavy periods fall at no fixed phase of the 50-period
// blocks), and never within kMinGap periods of the last (the loss takes a few periods to show).
constexpr std::uint64_t kHoldSpread = 200;
constexpr std::int64_t kMinGap = 50;
// While joints are down the operator's side sends a request in a period with probability 1 in
// kRequestOdds (at random: no period the blocks' phase could lock onto).
constexpr std::uint64_t kRequestOdds = 20;
// worst: while joints are down, a frame is damaged on a random drive's cable in a period with
// probability 1 in kDamageOdds (docs/timing.md "Damaged frames").
constexpr std::uint64_t kDamageOdds = 40;
// worst: a cut cable is repaired after this many periods (the drives' process-data watchdog, 100 ms,
// has taken them to SAFE-OP by then: the master re-arms them or recovers them).
constexpr std::int64_t kCutPeriods = 120;
// worst: the repair waits (at most this many periods more) for the period whose next one ends a
// sweep of the master's link diagnostics (docs/timing.md "Worst-path scenarios").
constexpr std::int64_t kMaxRepairWait = 200;
// worst and worst-ring: the cable cut, the cable into position kCutCable's port 0: the master's
// cable into the first slave. On the tree every slave falls silent; on the ring it opens the ring
// with every slave behind the break, the DC reference (the first slave) among them. The cable after
// the reference (1), which leaves the reference on the main side, gave a lighter period by
// instructions (docs/timing.md "Worst-path scenarios").
constexpr std::size_t kCutCable = 0;
// worst: the re-initialise of every joint sent again when the joints are not all Enabled this many
// periods after it (one that changed nothing would stall the scenario).
constexpr std::int64_t kBurstRetryPeriods = 50;

enum Task : std::uint8_t { kHandler, kManager, kParser, kRc, kSocket, kTasks };
constexpr const char* kTaskFiles[kTasks] = {"ethercat_handler", "joint_manager", "message_parser", "rc_tasks", "socket_handler"};
constexpr TaskId kTaskIds[kTasks] = {TaskId::ethercat_handler, TaskId::joint_manager, TaskId::message_parser, TaskId::rc_tasks,
                                     TaskId::socket_handler};

struct Samples {
  std::array<std::array<std::uint32_t, kMaxPeriods>, kTasks> ns;
};

class NoEvents final : public JointEventSink {
 public:
  void on_event(const JointEvent& /*event*/) noexcept override {}
};

hal::VirtualClock g_clock{hal::kNsPerSec};
TaskLinks g_links;
StartUpSlot<Samples> g_samples_slot;
StartUpSlot<drivers::SimulatedRobot> g_robot_slot;
StartUpSlot<drivers::JointBus> g_bus_slot;
StartUpSlot<drivers::SimulatedNic> g_nic_slot;           // the tree's one port
StartUpSlot<drivers::SimulatedNicPair> g_nic_pair_slot;  // the ring's two ports (worst-ring)
ecat::CaptureQueue g_capture;
ecat::CaptureWriter g_capture_file;
std::int64_t g_periods = 0;
char g_conditions[1024];
char g_load_at_start[64] = "n/a";
bool g_rt_applied = false;
bool g_real_time = true;  // --scheduling rt

// xorshift64: the power cycles' gaps from --seed, no heap, the same run for the same seed.
std::uint64_t next_random(std::uint64_t& state) noexcept {
  state ^= state << 13U;
  state ^= state >> 7U;
  state ^= state << 17U;
  return state;
}

std::uint32_t clamp_u32(hal::Nanoseconds v) noexcept {
  return v <= 0 ? 0U : v > 0xFFFFFFFF ? 0xFFFFFFFFU : static_cast<std::uint32_t>(v);
}

bool write_task(std::FILE* out, const void* context) noexcept {
  const auto task = static_cast<std::size_t>(*static_cast<const int*>(context));
  bool ok = std::fprintf(out, "# %s: one period's execution time in ns per line, period order\n%s", kTaskFiles[task], g_conditions) > 0;
  const Samples& s = g_samples_slot.emplace();
  for (std::int64_t k = 0; ok && k < g_periods; ++k) ok = std::fprintf(out, "%u\n", s.ns[task][static_cast<std::size_t>(k)]) > 0;
  return ok;
}

// The value of `TASK.KEY: VALUE` in pwcet.py's output; false when absent or not a number.
bool pwcet_figure(const char* path, const char* task, const char* key, double& value) noexcept {
  std::FILE* in = std::fopen(path, "r");
  if (in == nullptr) return false;
  char want[96];
  (void)std::snprintf(want, sizeof want, "%s.%s: ", task, key);
  char line[512];
  bool found = false;
  while (!found && std::fgets(line, sizeof line, in) != nullptr) {
    if (std::strncmp(line, want, std::strlen(want)) != 0) continue;
    char* end = nullptr;
    const char* at = line + std::strlen(want);
    value = std::strtod(at, &end);
    found = end != at;
  }
  (void)std::fclose(in);
  return found;
}

void copy_to_stdout(const char* path) noexcept {
  std::FILE* in = std::fopen(path, "r");
  if (in == nullptr) return;
  char line[1024];
  while (std::fgets(line, sizeof line, in) != nullptr) (void)std::fputs(line, stdout);
  (void)std::fclose(in);
}

// A diagnostics reset of every slave (ctl diag --reset: the handler zeroes the counters and
// publishes the table). The services' SDO transfers come through the socket handler (WcetOperatorLoad).
void reset_diagnostics() noexcept {
  DiagResetLink& reset = g_links.diag_reset;
  const std::uint64_t generation = DiagResetLink::generation_of(reset.requested.load(std::memory_order_relaxed)) + 1;
  reset.requested.store((generation << 32U) | DiagResetLink::kMaskBits, std::memory_order_release);
}

// The joint manager's joints by state (bit = kJoints index).
struct JointStates {
  JointMask enabled{0};
  JointMask error{0};
};

// The operator's side of the scenario: what a busy operator and a damaged robot put on the tasks.
class ScenarioDriver {
 public:
  // `ring`: the ring configuration (the frames damaged while joints are down and while every joint
  // is Enabled).
  // `diagnostics`: the master's link diagnostics, whose sweeps the repair is timed by.
  ScenarioDriver(drivers::SimulatedSegment& segment, const ecat::LinkDiagnostics& diagnostics, MessageSink<ControlRequest>& local,
                 MessageSource<ControlReply>& local_replies, std::uint64_t seed, bool ring) noexcept
      : segment_(segment),
        diagnostics_(diagnostics),
        local_(local),
        local_replies_(local_replies),
        random_(seed * 0x9E3779B97F4A7C15ULL + 1),
        ring_(ring) {}

  // Before period k's work.
  // `out`: the joints out of the exchange last period; `joints`, `lost`: the joint manager's.
  void before(const WcetStress& stress, std::int64_t k, JointMask out, const JointStates& joints, JointMask lost) noexcept {
    note_sweeps(k);
    if (stress.power_cycles) losses_when_due(stress, k, joints.enabled);
    // On the ring, also while every joint is Enabled: with the ring closed the copies of the damaged
    // exchange contradict each other and it is sent again in the same period (LinkStats::ring_repeats),
    // the ring's heaviest handler period; so also in every period that ends a diagnostics sweep
    // (note_sweeps). With the ring open (a cut) the frame is lost while the ring DC service writes
    // across the break. While joints are down, as on the tree: the recoveries' answers lost with the
    // main copy are asked for again (docs/redundancy.md "A copy lost in flight").
    if (stress.damaged_frames && ring_ && joints.enabled == kAllJoints && sweep_ends_at(k)) {
      (void)segment_.corrupt_port(random_drive(), 0, 1);
    } else if (stress.damaged_frames && (ring_ || joints.enabled != kAllJoints)) {
      damage_a_frame_at_random();
    }
    if (stress.services) reset_diagnostics();
    if (joints.enabled == kAllJoints) {
      next_burst_ = -1;
      // The message parser's heaviest period: as many requests as it takes in one period, each an
      // `initialize` of every joint while every joint is already initialised, so each is answered at
      // once naming the 21 unchanged joints (callgrind: the reply's text, format_joint_names, is most
      // of an answered request; a request left pending costs less). Sent in the first measured
      // period past the one instructions.sh leaves out, and in the first period every joint is
      // Enabled again after each loss.
      if (stress.repeated_requests && (k == 1 || !all_enabled_before_)) {
        for (std::size_t n = 0; n < MessageParser::kMaxRequestsPerStep; ++n) send(protocol::MessageType::initialize, kAllJoints);
      }
      all_enabled_before_ = true;
      return;
    }
    all_enabled_before_ = false;
    // The joint manager's heaviest period: the re-initialise of every joint, sent once every joint
    // is back in the exchange and none is lost or in Error, so each of the 21 takes all its steps in
    // one period while every joint is monitored.
    // Every other power cycle only (the first, the third, ...): after the others the re-initialise
    // goes at random periods as in `recovery` (an initialize that leaves unreachable joints out,
    // named in its reply; the parser's heaviest period is the repeated requests above).
    const bool burst = stress.burst && power_cycles_ % 2 == 1;
    const JointMask back = lost & ~out;
    const JointMask errored = joints.error & ~lost & ~out;
    if (burst && k >= next_burst_ && lost == 0 && out == 0 && errored == 0) {
      next_burst_ = k + kBurstRetryPeriods;
      send(protocol::MessageType::initialize, kAllJoints);
      return;
    }
    if (next_random(random_) % kRequestOdds != 0) return;
    // The operator's side while joints are down: once the master has a lost joint's drive back in
    // the exchange, its clear (the positions confirmed: the joints may have moved); a joint in Error
    // without a loss (its drive faulted while its cable was cut) the same (its reset step); then the
    // re-initialise of every joint not lost (the parser's heaviest request: each joint's three steps),
    // joint by joint, as run's runtime sends its own requests. With the burst the re-initialise waits
    // for every joint (above).
    if (back != 0 || errored != 0) {
      send(protocol::MessageType::clear_moved, back != 0 ? back : errored);
    } else if (!burst) {
      send(protocol::MessageType::initialize, kAllJoints & ~lost);
    }
  }

  // After the period: take the answers (the runtime's side, untimed).
  void after() noexcept {
    ControlReply reply;
    while (local_replies_.try_receive(reply)) {
    }
  }

  std::uint64_t power_cycles() const noexcept { return power_cycles_; }
  std::uint64_t damaged_frames() const noexcept { return segment_.counters().lost_port_corruption; }
  std::uint64_t cuts() const noexcept { return cuts_; }
  // Losses of joints the scenario caused (power cycles and cuts).
  std::uint64_t losses() const noexcept { return power_cycles_ + cuts_; }

 private:
  void send(protocol::MessageType type, JointMask joints) noexcept {
    ControlRequest request;
    request.sequence = ++sequence_;
    request.type = type;
    request.joints = joints;
    (void)local_.try_send(request);
  }

  // A frame damaged on a random drive's input cable: the ESCs it passed carry out its reads and
  // writes, the master gets a broken FCS and loses it, so a recovery's mailbox step loses its frame
  // (the master asks again: docs/master.md "Frames lost with a mailbox step").
  void damage_a_frame_at_random() noexcept {
    if (next_random(random_) % kDamageOdds != 0) return;
    (void)segment_.corrupt_port(random_drive(), 0, 1);
  }
  std::size_t random_drive() noexcept {
    return kJunctionCount + static_cast<std::size_t>(next_random(random_) % (kSlaveCount - kJunctionCount));
  }

  void losses_when_due(const WcetStress& stress, std::int64_t k, JointMask enabled) noexcept {
    if (cut_until_ >= 0) {
      if (k < cut_until_ || (!sweep_ends_at(k + 1) && k < cut_until_ + kMaxRepairWait)) return;
      (void)segment_.restore_link(kCutCable);
      cut_until_ = -1;
      last_loss_ = k;
      return;
    }
    if (enabled != kAllJoints || (losses() != 0 && k - last_loss_ < kMinGap)) return;
    if (next_loss_ < 0) next_loss_ = k + static_cast<std::int64_t>(next_random(random_) % kHoldSpread);
    if (k < next_loss_) return;
    next_loss_ = -1;
    last_loss_ = k;
    if (stress.cuts && losses() % 2 == 1) {
      // On the tree the cable into the first slave: every slave silent, the frames lost, until the
      // repair. On the ring (worst-ring) the ring opens there: every joint kept through the ring port.
      (void)segment_.cut_link(kCutCable);
      cut_until_ = k + kCutPeriods;
      ++cuts_;
      return;
    }
    for (std::size_t position = 0; position < segment_.slave_count(); ++position) {
      // A drive's mapping left as another drive's default: its recovery reads, rewrites and reads
      // it back (junctions have none: refused, nothing to do).
      if (stress.pdo_rewrites) (void)segment_.corrupt_pdo_mapping(position, drivers::PdoMappingFault::foreign_default);
      (void)segment_.power_cycle(position, g_clock.now());
    }
    ++power_cycles_;
  }

  // The link diagnostics' sweeps: one ends when the round robin of the ESC error-counter reads
  // wraps; the handler then publishes the table, and a second time in the same period after the
  // diagnostics reset of the services. The period after a repair (every drive re-armed, the
  // heaviest of the tree) is made one that ends a sweep: with the damaged frames' random draws
  // moving the cut, the two had stopped meeting (46916 -> 41455 instructions, docs/timing.md).
  void note_sweeps(std::int64_t k) noexcept {
    const std::uint64_t sweeps = diagnostics_.sweeps();
    if (sweeps == sweeps_seen_) return;
    // Seen before period k: the sweep ended in period k - 1.
    if (sweeps == sweeps_seen_ + 1 && last_sweep_end_ >= 0) sweep_gap_ = k - 1 - last_sweep_end_;
    sweeps_seen_ = sweeps;
    last_sweep_end_ = k - 1;
  }
  // Whether a sweep is due to end in period k (at the gap between the last two).
  bool sweep_ends_at(std::int64_t k) const noexcept {
    return sweep_gap_ > 0 && last_sweep_end_ >= 0 && (k - last_sweep_end_) % sweep_gap_ == 0;
  }

  drivers::SimulatedSegment& segment_;
  const ecat::LinkDiagnostics& diagnostics_;
  MessageSink<ControlRequest>& local_;
  MessageSource<ControlReply>& local_replies_;
  std::uint64_t random_;
  bool ring_;
  std::int64_t next_loss_{-1};
  std::int64_t last_loss_{0};
  std::int64_t cut_until_{-1};  // the first period the cut cable may be repaired (-1: none cut)
  std::uint64_t sweeps_seen_{0};
  std::int64_t last_sweep_end_{-1};
  std::int64_t sweep_gap_{0};
  std::uint64_t power_cycles_{0};
  std::uint64_t cuts_{0};
  std::uint64_t sequence_{0};
  std::int64_t next_burst_{-1};  // the first period the re-initialise of every joint may go (again)
  bool all_enabled_before_{true};  // every joint Enabled at the last call
};

// Where the last power cycle's recovery stood when the run ended (joint masks, bit = kJoints index).
void print_end_state(const JointManager& manager, drivers::JointBus& bus, const drivers::SimulatedSegment& segment,
                     JointMask last_out) noexcept {
  (void)std::printf("at_end_joints_out_of_exchange: 0x%06x\n", static_cast<unsigned>(last_out));
  (void)std::printf("at_end_joints_lost: 0x%06x\n", static_cast<unsigned>(manager.lost_joints()));
  (void)std::printf("at_end_joints_not_enabled:");
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const fsm::JointState state = manager.statuses()[j].state;
    if (state != fsm::JointState::enabled) (void)std::printf(" %s=%s", kJoints[j].name, fsm::to_string(state));
  }
  (void)std::printf("\n");
  (void)std::printf("at_end_slaves_recovering:");
  for (std::size_t position = 0; position < segment.slave_count(); ++position) {
    const ecat::RecoveryState state = bus.master().recovery_state(position);
    if (state == ecat::RecoveryState::idle) continue;
    (void)std::printf(" %s=%s(failures %u)", segment.slave(position).name, ecat::to_string(state),
                      static_cast<unsigned>(bus.master().recovery_failures(position)));
  }
  (void)std::printf("\n");
}

// `TASK.verdict`'s text in pwcet.py's output into `out` ("n/a" when absent).
void pwcet_verdict(const char* path, const char* task, char* out, std::size_t size) noexcept {
  (void)std::snprintf(out, size, "n/a");
  std::FILE* in = std::fopen(path, "r");
  if (in == nullptr) return;
  char want[96];
  (void)std::snprintf(want, sizeof want, "%s.verdict: ", task);
  char line[1024];
  while (std::fgets(line, sizeof line, in) != nullptr) {
    if (std::strncmp(line, want, std::strlen(want)) != 0) continue;
    line[std::strcspn(line, "\n")] = '\0';
    (void)std::snprintf(out, size, "%s", line + std::strlen(want));
    break;
  }
  (void)std::fclose(in);
}

// One line per task a reader takes alone: observed maximum, pWCET(1e-9) or n/a with the reason.
void print_task_summaries(const char* result_path) noexcept {
  const Samples& s = g_samples_slot.emplace();
  for (int t = 0; t < kTasks; ++t) {
    const auto& ns = s.ns[static_cast<std::size_t>(t)];
    const std::uint32_t observed = *std::max_element(ns.begin(), ns.begin() + g_periods);
    double pwcet = 0;
    double high = 0;
    char verdict[900];
    pwcet_verdict(result_path, kTaskFiles[t], verdict, sizeof verdict);
    if (pwcet_figure(result_path, kTaskFiles[t], "pwcet_1e-9_ns", pwcet) && pwcet_figure(result_path, kTaskFiles[t], "pwcet_1e-9_ci_high_ns", high)) {
      (void)std::printf("%s.summary: observed max %u ns; pWCET(1e-9) %.0f ns (interval up to %.0f ns)\n", kTaskFiles[t], observed, pwcet, high);
    } else {
      (void)std::printf("%s.summary: observed max %u ns; pWCET(1e-9) n/a (%s)\n", kTaskFiles[t], observed, verdict);
    }
  }
}

// The budget against Table I from pwcet.py's output (wcet_budget.hpp); true when a task is over.
bool print_budget(const char* result_path) noexcept {
  WcetBound bounds[kTasks];
  BudgetLine lines[kTasks];
  for (int t = 0; t < kTasks; ++t) {
    bounds[t].task = kTaskIds[t];
    bounds[t].given = pwcet_figure(result_path, kTaskFiles[t], "pwcet_1e-9_ci_high_ns", bounds[t].pwcet_ns);
  }
  judge_budget(Span<const WcetBound>(bounds), task_table(), Span<BudgetLine>(lines));
  bool over = false;
  for (int t = 0; t < kTasks; ++t) {
    const BudgetLine& line = lines[t];
    const char* task = kTaskFiles[t];
    if (line.period_ns > 0) {
      (void)std::printf("%s.budget_period_ns: %" PRId64 " (Table I CPU %d)\n", task, line.period_ns, line.cpu);
    } else {
      (void)std::printf("%s.budget_period_ns: n/a (event driven, Table I CPU %d)\n", task, line.cpu);
    }
    if (line.verdict == BudgetVerdict::within || line.verdict == BudgetVerdict::over) {
      (void)std::printf("%s.budget_share_of_period: %.4f\n", task, line.share);
      (void)std::printf("%s.budget_response_bound_ns: %.0f\n", task, line.response_ns);
    } else {
      (void)std::printf("%s.budget_share_of_period: n/a\n%s.budget_response_bound_ns: n/a\n", task, task);
    }
    (void)std::printf("%s.budget: %s\n", task, to_string(line.verdict));
    over = over || line.verdict == BudgetVerdict::over;
  }
  return over;
}

// The samples written into --out, pwcet.py run on them, the budget: bench wcet's exit status.
int analyse(const hal::OpenFile& dir, const char* out_dir, char* script, bool short_form, bool plot, std::int64_t block) noexcept {
  static char paths[kTasks][512];
  static const int indices[kTasks] = {0, 1, 2, 3, 4};
  char names[kTasks][64];
  char conditions[400];
  describe_wcet_conditions(conditions, sizeof conditions, g_load_at_start, g_real_time, g_rt_applied);
  const std::size_t used = std::strlen(g_conditions);
  (void)std::snprintf(g_conditions + used, sizeof g_conditions - used, "# conditions: %s\n", conditions);
  for (int t = 0; t < kTasks; ++t) {
    (void)std::snprintf(names[t], sizeof names[t], "%s.txt", kTaskFiles[t]);
    if (!write_file("wcet", dir, out_dir, names[t], write_task, &indices[t], paths[t], sizeof paths[t])) {
      return fail("bench", "wcet: cannot write the samples into --out");
    }
    (void)std::printf("samples_%s: %s\n", kTaskFiles[t], paths[t]);
  }
  char result_path[512];
  char png[512];
  (void)std::snprintf(result_path, sizeof result_path, "%s/pwcet.txt", out_dir);
  (void)std::snprintf(png, sizeof png, "%s/pwcet.png", out_dir);
  char bootstrap_flag[] = "--bootstrap";
  char bootstrap[8];
  (void)std::snprintf(bootstrap, sizeof bootstrap, "%d", short_form ? 100 : 500);
  char plot_flag[] = "--plot";
  char block_flag[] = "--block";
  char block_size[16];
  (void)std::snprintf(block_size, sizeof block_size, "%" PRId64, block);
  char* argv[14] = {script, bootstrap_flag, bootstrap, block_flag, block_size};
  int argc = 5;
  if (plot) {
    argv[argc++] = plot_flag;
    argv[argc++] = png;
  }
  for (auto& path : paths) argv[argc++] = path;
  argv[argc] = nullptr;
  (void)::unlink(result_path);  // pwcet.py's output is created anew (O_NOFOLLOW: never through a link)
  const int statistics = run_python(argv, result_path);
  copy_to_stdout(result_path);
  if (statistics != 0 && statistics != 2) {
    (void)std::fprintf(stderr, "rescue-motion bench: wcet: %s exited %d (its error above)\n", script, statistics);
    return 1;
  }

  (void)std::printf("conditions: %s\n", conditions);
  print_task_summaries(result_path);
  const bool over = print_budget(result_path);
  if (plot) (void)std::printf("png: %s\n", png);
  if (over) {
    (void)std::printf("wcet_verdict: over budget (a task's response bound exceeds its period)\n");
    return 3;
  }
  if (statistics == 2) {
    (void)std::printf("wcet_verdict: refused (a task's samples failed a test: no pWCET for it; see its verdict)\n");
    return 2;
  }
  (void)std::printf("wcet_verdict: every task has a pWCET within its budget\n");
  return 0;
}

// pwcet.py, scipy (and matplotlib with the plot), and --out created and opened as a directory of our
// own. 0, or the exit status.
int check_wcet_prerequisites(bool plot, const char* out_dir, char* script, std::size_t script_size,
                             Result<hal::OpenFile>& out) noexcept {
  char looked[1400];
  if (!find_script(nullptr, "pwcet.py", "toolchain/wcet/pwcet.py", script, script_size, looked, sizeof looked)) {
    (void)std::fprintf(stderr, "rescue-motion bench: wcet: no pwcet.py (looked: %s)\n", looked);
    return 1;
  }
  if (!python_imports("scipy, numpy")) return fail("bench", "wcet: /usr/bin/python3 cannot import scipy (apt install python3-scipy)");
  if (plot && !python_imports("matplotlib")) return fail("bench", "wcet: /usr/bin/python3 cannot import matplotlib (apt install python3-matplotlib), or --no-plot");
  if (::mkdir(out_dir, 0755) != 0 && errno != EEXIST) return fail("bench", "wcet: cannot create the --out directory");
  hal::FileProblem out_why;
  out = hal::open_trusted_directory(out_dir, hal::DirectoryUse::output, out_why);
  if (!out.ok()) {
    (void)std::fprintf(stderr, "rescue-motion bench: wcet: --out: %s\n", out_why.c_str());
    return 1;
  }
  return 0;
}

// The measuring thread's real-time set-up, and the conditions a figure is read with.
void apply_and_print_conditions(bool real_time) noexcept {
  // One thread steps every task: at the EtherCAT handler's SCHED_FIFO priority on its CPU (the last
  // one on a smaller machine), memory locked, so what is measured is the tasks' code and not the
  // other processes of a busy machine. Refused (no privilege): measured at normal scheduling, said so.
  // --scheduling normal (counting instructions under callgrind, ~50x slower): neither, so that the
  // run does not hold a CPU at FIFO for minutes; the rt: lines say both skipped.
  hal::RtConfig rt;
  rt.fifo_priority = real_time ? config::kEthercatHandlerPriority : 0;
  rt.cpu = real_time ? table_cpu_on_this_machine(config::kEthercatHandlerCpu) : -1;
  rt.prefault_stack_bytes = hal::kTaskStackPrefaultBytes;
  (void)std::printf("scheduling: %s\n", real_time ? "rt (SCHED_FIFO, pinned to a CPU)" : "normal (default scheduler, any CPU; --scheduling normal)");
  const hal::RtReport rt_report = hal::apply_rt_config(rt);
  rt_report.print(stdout);
  g_rt_applied = rt_report.fully_applied();
  g_real_time = real_time;
  // The conditions a figure is read with (docs/timing.md): PREEMPT_RT or not, the machine's load.
  read_load_average(g_load_at_start, sizeof g_load_at_start);
  (void)std::printf("preempt_rt: %s\n", kernel_is_preempt_rt() ? "yes" : "no");
  (void)std::printf("load_average_at_start: %s (1, 5, 15 min; /proc/loadavg)\n", g_load_at_start);
}

}  // namespace

// The measured periods: out of line, with stable names, for callgrind's --toggle-collect; each
// marks its end for toolchain/wcet/instructions.sh (core/app/tasks/period_mark.hpp).
__attribute__((noinline)) void wcet_handler_period(EthercatHandler& handler, drivers::JointCycleResult& result) noexcept {
  result = handler.cycle();
  handler.publish_figures(result, g_clock.now(), 0);
  mark_period_end("ethercat_handler");
}
__attribute__((noinline)) void wcet_joint_manager_period(JointManager& manager) noexcept {
  manager.step(g_clock.now());
  mark_period_end("joint_manager");
}
__attribute__((noinline)) void wcet_message_parser_period(MessageParser& parser) noexcept {
  parser.step(g_clock.now());
  mark_period_end("message_parser");
}
__attribute__((noinline)) void wcet_rc_period(kin::RcPeriod& rc, double t_s, JointMask out_of_service) noexcept {
  (void)rc.run(t_s, out_of_service, kin::JointVector::Zero());
  mark_period_end("rc_tasks");
}

namespace {

// What bench wcet's options ask for.
struct WcetOptions {
  bool short_form{false};
  std::int64_t periods{0};
  std::int64_t seed{0};
  std::int64_t block{0};
  const WcetScenarioSpec* scenario{nullptr};
  const char* out_dir{nullptr};
  bool plot{false};
  bool real_time{true};  // --scheduling rt (SCHED_FIFO, pinned) or normal
};

// bench wcet's options, checked. 0, or the exit status of the refusal.
int parse_wcet_options(const ParsedArgs& args, WcetOptions& options) noexcept {
  options.short_form = args.has("short");
  const Result<std::int64_t> periods = args.integer("periods", options.short_form ? kShortPeriods : kDefaultPeriods, 2000, kMaxPeriods);
  if (!periods.ok()) return fail("bench", "wcet: --periods must be 2000..200000 (40 blocks of 50 at least)", periods.error());
  const Result<std::int64_t> seed = args.integer("seed", 1, 0, 1'000'000);
  if (!seed.ok()) return fail("bench", "wcet: --seed must be 0..1000000", seed.error());
  const Result<std::int64_t> block = args.integer("block", 50, 1, 100000);
  if (!block.ok()) return fail("bench", "wcet: --block must be 1..100000", block.error());
  if (periods.value() / block.value() < 40) return fail("bench", "wcet: --periods must hold at least 40 blocks of --block periods (pwcet.py's least)");
  const char* scenario_name = args.value("scenario") != nullptr ? args.value("scenario") : "worst";
  const WcetScenarioSpec* scenario = find_wcet_scenario(scenario_name);
  if (scenario == nullptr) {
    (void)std::fprintf(stderr, "rescue-motion bench: wcet: unknown scenario '%s' (known:", scenario_name);
    for (const WcetScenarioSpec& s : wcet_scenarios()) (void)std::fprintf(stderr, " %s", s.name);
    (void)std::fprintf(stderr, ")\n");
    return 1;
  }
  options.periods = periods.value();
  options.seed = seed.value();
  options.block = block.value();
  options.scenario = scenario;
  options.out_dir = args.value("out") != nullptr ? args.value("out") : "/tmp/rescue-wcet";
  options.plot = !args.has("no-plot");
  const char* scheduling = args.value("scheduling") != nullptr ? args.value("scheduling") : "rt";
  options.real_time = std::strcmp(scheduling, "rt") == 0;
  if (!options.real_time && std::strcmp(scheduling, "normal") != 0) return fail("bench", "wcet: --scheduling must be rt or normal");
  return 0;
}

// The tasks as run_firmware wires them (one thread steps them all), and what the scenario puts on them.
struct WcetRig {
  Samples* samples{nullptr};
  drivers::SimulatedRobot* robot{nullptr};
  drivers::JointBus* bus{nullptr};
  TaskPorts* ports{nullptr};
  ErrorJointsStorageWorker* storage_worker{nullptr};
  JointManager* manager{nullptr};
  MessageParser* parser{nullptr};
  EthercatHandler* handler{nullptr};
  kin::RcPeriod* rc{nullptr};
  ScenarioDriver* driver{nullptr};
  WcetOperatorLoad* operator_load{nullptr};
  std::int64_t motion_periods{0};
  std::int64_t rc_k{0};
  char state_dir[32] = "/tmp/rescue-bench-wcet-XXXXXX";
};

// Init: everything that may allocate, the network brought up, the capture file opened. 0, or the
// exit status.
int wire_wcet_tasks(const WcetOptions& options, WcetRig& rig) noexcept {
  if (!g_samples_slot.reserve() || !g_robot_slot.reserve() || !g_bus_slot.reserve() ||
      !(options.scenario->ring ? g_nic_pair_slot.reserve() : g_nic_slot.reserve())) {
    return fail("bench", "wcet: not enough memory for the samples and the simulated robot");
  }
  rig.samples = &g_samples_slot.emplace();
  drivers::RobotSegmentOptions robot_options;
  robot_options.seed = static_cast<std::uint64_t>(options.seed);
  robot_options.ring = options.scenario->ring;
  drivers::SimulatedRobot& robot = g_robot_slot.emplace(robot_options, g_clock.now());
  rig.robot = &robot;
  if (!robot.status().ok()) return fail("bench", "wcet: cannot build the simulated robot", robot.status().error());
  drivers::JointBus* bus_at = nullptr;
  if (options.scenario->ring) {
    // Both master ports (docs/redundancy.md), as run --nic sim --ring-nic sim wires them.
    drivers::SimulatedNicPair& pair = g_nic_pair_slot.emplace(robot.segment(), g_clock);
    if (!pair.status().ok()) return fail("bench", "wcet: cannot build the ring's two ports", pair.status().error());
    bus_at = &g_bus_slot.emplace(pair.main(), drivers::kRobotRingNetworkPlan);
    bus_at->master().use_ring(pair.ring());
  } else {
    bus_at = &g_bus_slot.emplace(g_nic_slot.emplace(robot.segment(), g_clock), drivers::kRobotNetworkPlan);
  }
  drivers::JointBus& bus = *bus_at;
  rig.bus = &bus;
  if (mkdtemp(rig.state_dir) == nullptr) return fail("bench", "wcet: cannot create a temporary state directory");
  static ErrorJointsFileStorage storage(rig.state_dir);
  static TaskPorts ports(g_links);
  static hal::ManualWallClock wall;
  static NoEvents events;
  static ErrorJointsStorageWorker storage_worker(ports.storage_worker_requests(), ports.storage_worker_results(), storage);
  static JointManager manager(ports.joint_manager(storage, wall, events));
  manager.set_auto_clear_power_cycled(true);  // a power-cycled joint returns through the clear (run --auto-clear-power-cycled)
  (void)manager.restore(g_clock.now());
  static MessageParser parser(ports.message_parser());
  ecat::MasterOptions master_options;
  master_options.online_recovery = true;  // as run: returning slaves back to OP while cycling
  const Status up = bus.bring_up(master_options);
  if (!up.ok()) return fail("bench", "wcet: bring-up failed", up.error());
  static EthercatHandler handler(bus, ports.ethercat_handler(), 0);
  static kin::RcPeriod rc(kin::ready_posture());
  static SpscMessageSink<ControlRequest, TaskLinks::kRequestQueueDepth> local(g_links.local_requests);
  static SpscMessageSource<ControlReply, TaskLinks::kReplyQueueDepth> local_replies(g_links.local_replies);
  static ScenarioDriver driver(robot.segment(), bus.master().diagnostics(), local, local_replies, static_cast<std::uint64_t>(options.seed),
                               options.scenario->ring);
  static WcetOperatorLoad operator_load(ports.socket_handler());
  if (const Status opened = operator_load.open(); !opened.ok()) return fail("bench", "wcet: cannot open the socket handler on 127.0.0.1", opened.error());
  rig.ports = &ports;
  rig.storage_worker = &storage_worker;
  rig.manager = &manager;
  rig.parser = &parser;
  rig.handler = &handler;
  rig.rc = &rc;
  rig.driver = &driver;
  rig.operator_load = &operator_load;
  char capture_path[512];
  (void)std::snprintf(capture_path, sizeof capture_path, "%s/capture.pcapng", options.out_dir);
  (void)::unlink(capture_path);
  if (!g_capture_file.open(capture_path, ecat::CaptureWriterOptions{}).ok()) return fail("bench", "wcet: cannot open the capture file in --out");
  return 0;
}

// The RC period's time into the rescue motion, which repeats.
double next_rc_time_s(WcetRig& rig) noexcept {
  return static_cast<double>(rig.rc_k++ % (rig.motion_periods > 0 ? rig.motion_periods : 1)) * 0.001;
}

// Bring-up and settling: the same work, outside the measured functions (callgrind counts only the
// measured periods: toolchain/wcet/instructions.sh).
drivers::JointCycleResult unmeasured_period(WcetRig& rig) noexcept {
  g_clock.sleep_until(rig.bus->next_wakeup());
  const drivers::JointCycleResult r = rig.handler->cycle();
  rig.handler->publish_figures(r, g_clock.now(), 0);
  rig.manager->step(g_clock.now());
  (void)rig.storage_worker->serve_one();
  rig.parser->step(g_clock.now());
  (void)rig.rc->run(next_rc_time_s(rig), r.out | rig.manager->lost_joints(), kin::JointVector::Zero());
  return r;
}

// Measured period k: each task's execution time into the samples.
drivers::JointCycleResult measured_period(WcetRig& rig, const hal::TscTimer& timer, std::int64_t k) noexcept {
  g_clock.sleep_until(rig.bus->next_wakeup());
  drivers::JointCycleResult r;
  const std::uint64_t ts = timer.start();
  wcet_socket_handler_period(rig.operator_load->handler(), g_clock.now());
  const std::uint64_t ts_end = timer.stop();
  const std::uint64_t t0 = timer.start();
  wcet_handler_period(*rig.handler, r);
  const std::uint64_t t1 = timer.stop();
  const std::uint64_t t2_start = timer.start();
  wcet_joint_manager_period(*rig.manager);
  const std::uint64_t t2 = timer.stop();
  (void)rig.storage_worker->serve_one();  // a thread of its own in run: untimed
  const std::uint64_t t3 = timer.start();
  wcet_message_parser_period(*rig.parser);
  const std::uint64_t t4 = timer.stop();
  const double t_s = next_rc_time_s(rig);
  const JointMask out_of_service = r.out | rig.manager->lost_joints();
  const std::uint64_t t5 = timer.start();
  wcet_rc_period(*rig.rc, t_s, out_of_service);
  const std::uint64_t t6 = timer.stop();
  const auto at = static_cast<std::size_t>(k);
  rig.samples->ns[kHandler][at] = clamp_u32(timer.to_ns(t1 - t0));
  rig.samples->ns[kManager][at] = clamp_u32(timer.to_ns(t2 - t2_start));
  rig.samples->ns[kParser][at] = clamp_u32(timer.to_ns(t4 - t3));
  rig.samples->ns[kRc][at] = clamp_u32(timer.to_ns(t6 - t5));
  rig.samples->ns[kSocket][at] = clamp_u32(timer.to_ns(ts_end - ts));
  return r;
}

// The network to OP, every joint initialised, then settling. 0, or the exit status.
int reach_op_and_settle(WcetRig& rig, int& to_op) noexcept {
  to_op = 0;
  while (to_op < kMaxCyclesToOp && unmeasured_period(rig).state != ecat::MasterState::op) ++to_op;
  if (to_op == kMaxCyclesToOp) return fail("bench", "wcet: the network did not reach OP");
  MessageSink<JointCommand>& commands = *rig.ports->message_parser().joint_commands;
  for (const JointCommand& c : initialize_robot_commands(kAllJoints)) {
    // cppcheck-suppress useStlAlgorithm
    if (!commands.try_send(c)) return fail("bench", "wcet: joint handle queue full");
  }
  for (int i = 0; i < kSettleCycles; ++i) (void)unmeasured_period(rig);
  return 0;
}

// What the measured periods saw of the scenario.
struct WcetRunFigures {
  int to_op{0};
  std::uint64_t periods_all_enabled{0};
  std::uint64_t periods_with_lost{0};
  JointMask last_out{0};
  std::int64_t longest_recovery{-1};  // periods from a power cycle to every joint Enabled again
  std::uint64_t recoveries{0};
  HeapGuardCounters heap{};
  std::uint64_t rt_rests{0};  // RtDutyRest's rests between periods
};

// The measured periods, the scenario's stress before each: nothing may allocate.
void measure_periods(const WcetOptions& options, WcetRig& rig, const hal::TscTimer& timer, WcetRunFigures& figures) noexcept {
  declare_init_complete(HeapGuardMode::count);
  bool capture_on = false;
  std::uint64_t cycles_seen = 0;
  std::int64_t down_since = -1;  // the period of the power cycle not yet recovered from
  bool went_down = false;
  RtDutyRest duty;  // no real-time throttling inside a measured period
  for (std::int64_t k = 0; k < options.periods; ++k) {
    const WcetStress stress = wcet_stress(options.scenario->id, k, options.periods);
    if (stress.services && !capture_on) {
      rig.bus->master().set_tap(ecat::capture_queue_tap, &g_capture);  // capture on: every frame queued for the logger
      capture_on = true;
    }
    JointStates joints;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const fsm::JointState state = rig.manager->statuses()[j].state;
      if (state == fsm::JointState::enabled) joints.enabled |= JointMask{1} << j;
      if (state == fsm::JointState::error) joints.error |= JointMask{1} << j;
    }
    const JointMask enabled = joints.enabled;
    if (down_since >= 0 && enabled != kAllJoints) went_down = true;
    if (down_since >= 0 && went_down && enabled == kAllJoints) {
      figures.longest_recovery = std::max(figures.longest_recovery, k - down_since);
      ++figures.recoveries;
      down_since = -1;
    }
    rig.driver->before(stress, k, figures.last_out, joints, rig.manager->lost_joints());
    rig.operator_load->before(stress.services);
    if (rig.driver->losses() != cycles_seen) {
      cycles_seen = rig.driver->losses();
      down_since = k;
      went_down = false;
    }
    figures.last_out = measured_period(rig, timer, k).out;
    rig.driver->after();
    rig.operator_load->after();
    if (capture_on) (void)g_capture.drain(g_capture_file, ecat::CaptureQueue::kCapacity);  // the logger's side, untimed
    figures.periods_all_enabled += enabled == kAllJoints ? 1U : 0U;
    figures.periods_with_lost += rig.manager->lost_joints() != 0 ? 1U : 0U;
    duty.between_periods();
  }
  figures.rt_rests = duty.rests();
  figures.heap = heap_guard_counters();
}

// What the ring did (worst-ring; n/a on the tree): its breaks and repairs, the ring DC service's
// calibrations across a break and the island's time reads (one FRMW in the ring copy a period), the
// exchanges repeated after a change in flight.
void print_ring_figures(ecat::Master& master) noexcept {
  const ecat::RingStatus& ring = master.ring_status();
  if (ring.state == ecat::RingState::none) {
    (void)std::printf("ring_breaks: n/a (the tree)\nring_repairs: n/a\nring_dc_calibrations: n/a\nring_dc_island_reads: n/a\nring_repeats: n/a\n");
    return;
  }
  const ecat::RingDcStatus& dc = master.ring_dc_status();
  (void)std::printf("ring_breaks: %" PRIu64 "\n", ring.breaks);
  (void)std::printf("ring_repairs: %" PRIu64 "\n", ring.repairs);
  (void)std::printf("ring_dc_calibrations: %" PRIu64 " (latch and reads of every DC slave behind the break)\n", dc.calibrations);
  (void)std::printf("ring_dc_island_reads: %" PRIu64 " (the island's time FRMW in the ring copy, behind the break)\n",
                    dc.island_reads);
  (void)std::printf("ring_repeats: %" PRIu64 " (exchanges sent again: the ring closed while a frame was in flight)\n",
                    master.link().stats().ring_repeats);
}

void print_run_figures(const WcetOptions& options, const WcetRig& rig, const hal::TscTimer& timer,
                       const WcetRunFigures& figures) noexcept {
  (void)std::printf("scenario: %s (%s)\n", options.scenario->name, options.scenario->what);
  (void)std::printf("form: %s\n", options.short_form ? "short (CI: the method and the refusal, not the bound)" : "full");
  (void)std::printf("clock: virtual (the simulated robot; execution times by %s on the host)\n", hal::to_string(timer.source()));
  (void)std::printf("measured_periods: %" PRId64 " periods per task\n", options.periods);
  (void)std::printf("cycles_to_op: %d cycles\n", figures.to_op);
  (void)std::printf("power_cycles_of_every_slave: %" PRIu64 "\n", rig.driver->power_cycles());
  (void)std::printf("cable_cuts_repaired: %" PRIu64 " (the cable into position %zu, repaired after %" PRId64
                    " periods or more: in the period before one that ends a sweep of the link diagnostics)\n",
                    rig.driver->cuts(), kCutCable, kCutPeriods);
  print_ring_figures(rig.bus->master());
  (void)std::printf("recoveries_to_every_joint_enabled: %" PRIu64 "\n", figures.recoveries);
  if (figures.longest_recovery >= 0) {
    (void)std::printf("longest_recovery: %" PRId64 " periods (power cycle or cut to every joint Enabled)\n", figures.longest_recovery);
  } else {
    (void)std::printf("longest_recovery: n/a\n");
  }
  const WcetOperatorLoad& load = *rig.operator_load;
  (void)std::printf("sdo_transfers: %" PRIu64 " (%" PRIu64 " answered ok)\n", load.sdo_transfers(), load.sdo_transfers_ok());
  (void)std::printf("operator_datagrams: %" PRIu64 " sent, %" PRIu64 " answered, %" PRIu64 " send failures\n", load.datagrams_sent(),
                    load.answers(), load.send_failures());
  (void)std::printf("socket_handler_max_datagrams_per_wakeup: %zu (its budget %zu)\n", load.handler().max_per_wakeup(),
                    SocketHandler::kBudget);
  const ecat::RecoveryStats& recovery = rig.bus->master().recovery_stats();
  (void)std::printf("master_recoveries: %u slaves recovered, %u attempts failed, %u refused\n", static_cast<unsigned>(recovery.recovered),
                    static_cast<unsigned>(recovery.failed), static_cast<unsigned>(recovery.refused));
  (void)std::printf("damaged_frames: %" PRIu64 " (lost at the master, broken FCS)\n", rig.driver->damaged_frames());
  const ecat::MailboxStats& mailbox = rig.bus->master().mailbox().stats();
  (void)std::printf("mailbox_timeouts: %" PRIu64 "\n", mailbox.timeouts);
  (void)std::printf("mailbox_repeat_requests: %" PRIu64 "\n", mailbox.repeat_requests);
  (void)std::printf("mailbox_rewrites: %" PRIu64 "\n", mailbox.rewrites);
  (void)std::printf("mailbox_repeats_dropped: %" PRIu64 "\n", mailbox.duplicates_dropped);
  (void)std::printf("periods_every_joint_enabled: %" PRIu64 "\n", figures.periods_all_enabled);
  (void)std::printf("periods_with_lost_joints: %" PRIu64 "\n", figures.periods_with_lost);
  print_end_state(*rig.manager, *rig.bus, rig.robot->segment(), figures.last_out);
  (void)std::printf("rt_rests_between_periods: %" PRIu64 " (10 ms after every 100 ms: no real-time throttling inside a period)\n",
                    figures.rt_rests);
  (void)std::printf("heap_allocations_after_init: %" PRIu64 " allocations\n", figures.heap.allocations);
}

}  // namespace

int bench_wcet(const ParsedArgs& args) noexcept {
  WcetOptions options;
  const int parsed = parse_wcet_options(args, options);
  if (parsed != 0) return parsed;
  // The statistics' prerequisites first, before the measuring.
  char script[640];
  Result<hal::OpenFile> out = make_error(Errc::not_found, "not opened");
  const int ready = check_wcet_prerequisites(options.plot, options.out_dir, script, sizeof script, out);
  if (ready != 0) return ready;
  print_bench_header(stdout, "wcet");
  apply_and_print_conditions(options.real_time);

  static WcetRig rig;
  const int wired = wire_wcet_tasks(options, rig);
  if (wired != 0) return wired;
  const hal::TscTimer timer = hal::TscTimer::calibrate();
  rig.motion_periods = static_cast<std::int64_t>(rig.rc->motion().duration_s() * 1000.0);
  WcetRunFigures figures;
  const int settled = reach_op_and_settle(rig, figures.to_op);
  if (settled != 0) return settled;

  measure_periods(options, rig, timer, figures);
  (void)g_capture_file.close();
  g_periods = options.periods;

  print_run_figures(options, rig, timer, figures);
  (void)std::snprintf(g_conditions, sizeof g_conditions, "# bench wcet --scenario %s --periods %" PRId64 " --block %" PRId64 " --seed %" PRId64 "\n",
                      options.scenario->name, options.periods, options.block, options.seed);
  (void)std::remove(rig.state_dir);
  if (figures.heap.allocations != 0) return fail("bench", "wcet: heap allocation after init complete");

  return analyse(out.value(), options.out_dir, script, options.short_form, options.plot, options.block);
}

}  // namespace rescue::app
