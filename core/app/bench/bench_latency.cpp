#include "core/app/bench/bench_latency.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cerrno>
#include <cstdlib>
#include <atomic>
#include <cstring>
#include <thread>

#include "core/app/bench/bench_header.hpp"
#include "core/app/config/firmware_config.hpp"
#include "core/app/config/task_table.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/runtime/nic_factory.hpp"
#include "core/app/runtime/period_schedule.hpp"
#include "core/app/runtime/task_ports.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/memory/start_up_slot.hpp"
#include "core/timing/latency_histogram.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/clock.hpp"

extern char** environ;  // NOLINT(readability-redundant-declaration): posix_spawn passes it on

namespace rescue::app {
namespace {

// One unsigned decimal number after optional blanks; advances `at` past it. False: none, or too large.
bool parse_decimal(const char*& at, std::uint64_t& value) noexcept {
  while (*at == ' ' || *at == '\t') ++at;
  if (*at < '0' || *at > '9') return false;
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(at, &end, 10);
  if (errno != 0) return false;
  value = v;
  at = end;
  return true;
}

// cyclictest's summary line "<label> <value> ...": the first task's value.
bool summary_value(const char* line, const char* label, std::uint64_t& value) noexcept {
  const std::size_t n = std::strlen(label);
  if (std::strncmp(line, label, n) != 0) return false;
  const char* at = line + n;
  return parse_decimal(at, value);
}

// The EtherCAT handler's settings (the task table: config/firmware_config.hpp).
constexpr int kHandlerPriority = config::kEthercatHandlerPriority;
constexpr int kHandlerCpu = config::kEthercatHandlerCpu;
constexpr hal::Nanoseconds kPeriod = config::kEthercatHandlerPeriodNs;
constexpr double kDefaultPeriods = 10000;
constexpr std::size_t kCyclictestBuckets = 2000;  // us; beyond: overflow (counted in max only)

LatencyHistogram g_ours;
LatencyHistogram g_reference;

struct Figures {
  double p50_ns{0};
  double p99_ns{0};
  double max_ns{0};
  double min_ns{0};
  double mean_ns{0};
  std::uint64_t count{0};
};


constexpr int kMaxPeriodsToOp = 5000;

struct LoopSetup {
  bool pm_qos{true};   // the process's CPU wake-up latency request, as `run`'s tasks hold it
  bool failed{false};  // the handler did not reach OP
  std::uint64_t heap_allocations{0};  // during the measured periods
};

// The EtherCAT handler's real loop (runtime/task_loops.cpp handler_task): its thread's real-time
// set-up as `run` applies it (priority, CPU, stack, timer slack, PM QoS), then per period the same wake
// (`wake_at`: clock_nanosleep to the master's release, the clock read at once) and the same
// `EthercatHandler::cycle()` against the in-process simulated robot on the wall clock, with the
// master's receive wait; the wake-up latency is recorded as cyclictest records its own.
// What our loop tells the interleaved reference loop (below) each period.
struct Interleaving {
  std::atomic<hal::Nanoseconds> our_release{-1};    // ours, published before it sleeps
  std::atomic<hal::Nanoseconds> our_cycle_end{-1};  // when our latest cycle ended
  std::atomic<bool> reference_ready{false};         // the reference thread's set-up is done (it allocates)
  std::atomic<bool> measuring{false};               // our measured periods have begun
  std::atomic<bool> stop{false};
  std::uint64_t skipped{0};  // reference periods not recorded: our cycle ran past their release
};

// The thread set-up both loops share: the EtherCAT handler's priority, CPU, stack, timer slack, PM QoS.
hal::RtReport apply_handler_rt(int cpu, const LoopSetup& setup) noexcept {
  hal::RtConfig config;
  config.lock_memory = false;  // once for the process
  config.prefault_stack_bytes = hal::kTaskStackPrefaultBytes;
  config.fifo_priority = kHandlerPriority;
  config.cpu = cpu;
  config.timer_slack_ns = config::kTaskTimerSlackNs;
  config.cpu_wakeup_latency_us = setup.pm_qos ? config::kCpuWakeupLatencyUs : -1;
  return hal::apply_rt_config(config);
}

// cyclictest's loop (sleep to an absolute release, read the clock at once, no work) in a second
// thread on our loop's CPU at its priority, released half a period after each of our releases: the
// two loops meet the same host in the same millisecond, so a slow stretch of the host (this VM's
// are 0.5 to 20 ms long, seen by cyclictest itself) counts against both, which one-after-the-other
// runs cannot give. A period whose release fell inside our cycle is skipped and counted: the same
// priority on one CPU means it waited for our work, not for the OS.
void reference_loop(Interleaving& shared, hal::Clock& clock, int cpu, const LoopSetup* setup, hal::RtReport* report) noexcept {
  *report = apply_handler_rt(cpu, *setup);
  shared.reference_ready.store(true, std::memory_order_release);
  hal::Nanoseconds last = -1;
  while (!shared.stop.load(std::memory_order_acquire)) {
    const hal::Nanoseconds ours = shared.our_release.load(std::memory_order_acquire);
    if (!shared.measuring.load(std::memory_order_acquire) || ours == last) {
      clock.sleep_until(clock.now() + kPeriod / 4);  // not yet, or our loop has not moved on
      continue;
    }
    last = ours;
    const hal::Nanoseconds release = ours + kPeriod / 2;
    if (release <= clock.now()) {
      ++shared.skipped;
      continue;
    }
    const hal::Nanoseconds woke = wake_at(clock, release);
    if (shared.our_cycle_end.load(std::memory_order_acquire) >= release) {
      ++shared.skipped;
      continue;
    }
    g_reference.record(static_cast<std::uint64_t>(woke - release));
  }
}

void our_loop(EthercatHandler& handler, hal::Clock& clock, std::uint64_t periods, int cpu, LoopSetup* setup,
              Interleaving* shared, hal::RtReport* report) noexcept {
  *report = apply_handler_rt(cpu, *setup);
  // The reference thread's set-up allocates (glibc's pthread_getattr_np, for the stack prefault): init
  // is complete only once it is done. On a loaded host that thread can start milliseconds after this
  // one; counted, its set-up read as allocations of our loop (CI under stress-ng: 3).
  while (!shared->reference_ready.load(std::memory_order_acquire)) clock.sleep_until(clock.now() + kPeriod / 10);
  drivers::JointBus& bus = handler.bus();
  for (int to_op = 0;; ++to_op) {
    (void)wake_at(clock, bus.next_wakeup());
    if (handler.cycle().state == ecat::MasterState::op) break;
    if (to_op == kMaxPeriodsToOp) {
      setup->failed = true;
      return;
    }
  }
  declare_init_complete(HeapGuardMode::count);  // from here on every allocation is counted
  const std::uint64_t heap_before = heap_guard_counters().allocations;
  shared->measuring.store(true, std::memory_order_release);
  for (std::uint64_t i = 0; i < periods; ++i) {
    const hal::Nanoseconds release = bus.next_wakeup();
    shared->our_release.store(release, std::memory_order_release);
    const hal::Nanoseconds woke = wake_at(clock, release);
    g_ours.record(woke > release ? static_cast<std::uint64_t>(woke - release) : 0);
    const drivers::JointCycleResult r = handler.cycle();
    handler.publish_figures(r, clock.now(), 0);  // as run's loop does after each cycle (task_loops.cpp)
    shared->our_cycle_end.store(clock.now(), std::memory_order_release);
  }
  shared->stop.store(true, std::memory_order_release);
  setup->heap_allocations = heap_guard_counters().allocations - heap_before;
}

// Runs cyclictest and reads its histogram (one line per us, "# Max Latencies:" ...) from a pipe.
bool run_cyclictest(std::uint64_t periods, int cpu, bool pm_qos, Figures& out, char* why, std::size_t why_size) noexcept {
  char prio[16];
  char affinity[16];
  char interval[24];
  char loops[24];
  char histogram[16];
  (void)std::snprintf(prio, sizeof prio, "-p%d", kHandlerPriority);
  (void)std::snprintf(affinity, sizeof affinity, "-a%d", cpu);
  (void)std::snprintf(interval, sizeof interval, "-i%" PRId64, kPeriod / 1000);
  (void)std::snprintf(loops, sizeof loops, "-l%" PRIu64, periods);
  (void)std::snprintf(histogram, sizeof histogram, "-h%zu", kCyclictestBuckets);
  char name[] = "cyclictest";
  char m[] = "-m";
  char q[] = "-q";
  char t1[] = "-t1";
  char laptop[] = "--laptop";  // without its /dev/cpu_dma_latency request (bench latency --no-pm-qos)
  char* argv[] = {name, m, q, t1, prio, affinity, interval, loops, histogram, pm_qos ? nullptr : laptop, nullptr};
  (void)std::fflush(stdout);
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) {
    (void)std::snprintf(why, why_size, "pipe failed");
    return false;
  }
  posix_spawn_file_actions_t actions;
  (void)posix_spawn_file_actions_init(&actions);
  (void)posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  (void)posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "cyclictest", &actions, nullptr, argv, environ);
  (void)posix_spawn_file_actions_destroy(&actions);
  (void)close(pipe_fds[1]);
  if (spawned != 0) {
    (void)close(pipe_fds[0]);
    (void)std::snprintf(why, why_size, "cyclictest not found (Debian package rt-tests, toolchain/setup.sh)");
    return false;
  }
  std::FILE* in = fdopen(pipe_fds[0], "r");
  if (in == nullptr) {
    (void)close(pipe_fds[0]);
    (void)std::snprintf(why, why_size, "fdopen failed");
    return false;
  }
  static std::uint64_t counts[kCyclictestBuckets];
  std::memset(counts, 0, sizeof counts);
  char line[512];
  while (std::fgets(line, sizeof line, in) != nullptr) {
    std::uint64_t us = 0;
    std::uint64_t count = 0;
    const char* rest = line;
    if (line[0] != '#' && parse_decimal(rest, us) && parse_decimal(rest, count) && us < kCyclictestBuckets) {
      counts[us] = count;
      out.count += count;
    } else if (summary_value(line, "# Max Latencies:", us)) {
      out.max_ns = static_cast<double>(us) * 1000.0;
    } else if (summary_value(line, "# Min Latencies:", us)) {
      out.min_ns = static_cast<double>(us) * 1000.0;
    } else if (summary_value(line, "# Avg Latencies:", us)) {
      out.mean_ns = static_cast<double>(us) * 1000.0;
    }
  }
  (void)std::fclose(in);
  int status = 0;
  (void)waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || out.count == 0) {
    (void)std::snprintf(why, why_size, "cyclictest failed (exit status %d, %" PRIu64 " samples)",
                        WIFEXITED(status) ? WEXITSTATUS(status) : -1, out.count);
    return false;
  }
  // Percentiles from the per-us histogram: the us of the rank's sample (cyclictest's resolution).
  const double ranks[] = {0.50, 0.99};
  double* targets[] = {&out.p50_ns, &out.p99_ns};
  for (std::size_t r = 0; r < 2; ++r) {
    std::uint64_t seen = 0;
    const auto rank = static_cast<std::uint64_t>(static_cast<double>(out.count) * ranks[r] + 0.999999);
    for (std::size_t us = 0; us < kCyclictestBuckets; ++us) {
      seen += counts[us];
      if (seen >= rank) {
        *targets[r] = static_cast<double>(us) * 1000.0;
        break;
      }
    }
  }
  return true;
}

void print_figures(const char* who, const Figures& f) noexcept {
  (void)std::printf("%s_periods: %" PRIu64 " periods\n", who, f.count);
  (void)std::printf("%s_latency_min: %.0f ns\n", who, f.min_ns);
  (void)std::printf("%s_latency_mean: %.0f ns\n", who, f.mean_ns);
  (void)std::printf("%s_latency_p50: %.0f ns\n", who, f.p50_ns);
  (void)std::printf("%s_latency_p99: %.0f ns\n", who, f.p99_ns);
  (void)std::printf("%s_latency_max: %.0f ns\n", who, f.max_ns);
}

Figures figures_of(const LatencyHistogram& h) noexcept {
  Figures f;
  f.count = h.count();
  f.min_ns = static_cast<double>(h.min());
  f.mean_ns = h.mean();
  f.p50_ns = static_cast<double>(h.percentile(50.0));
  f.p99_ns = static_cast<double>(h.percentile(99.0));
  f.max_ns = static_cast<double>(h.max());
  return f;
}

double whole_us(double ns) noexcept { return std::floor(ns / 1000.0) * 1000.0; }

double ratio(double ours, double floor) noexcept { return floor > 0.0 ? ours / floor : 0.0; }

}  // namespace

int bench_latency(const ParsedArgs& args) noexcept {
  const Result<double> periods_arg = args.number("periods", kDefaultPeriods, 100.0, 1e9);
  if (!periods_arg.ok()) return fail("bench", "--periods N", periods_arg.error());
  const auto periods = static_cast<std::uint64_t>(periods_arg.value());
  print_bench_header(stdout, "latency");
  const int cpu = table_cpu_on_this_machine(kHandlerCpu);
  (void)std::printf("preempt_rt: %s\n", kernel_is_preempt_rt() ? "yes (/sys/kernel/realtime = 1)" : "no (stock kernel)");
  (void)std::printf("period: %" PRId64 " ns\n", kPeriod);
  (void)std::printf("priority: SCHED_FIFO %d (the EtherCAT handler's)\n", kHandlerPriority);
  (void)std::printf("task_cpu: %d (the handler's CPU %d, or the last one on fewer CPUs)\n", cpu, kHandlerCpu);
  LoopSetup setup;
  setup.pm_qos = !args.has("no-pm-qos");
  (void)std::printf("loop: the EtherCAT handler's (wake_at, then EthercatHandler::cycle on the in-process simulated robot)\n");
  (void)std::printf("pm_qos: %s\n", setup.pm_qos ? "held at 0 us by both loops (/dev/cpu_dma_latency, as `run` and cyclictest)"
                                                  : "not held by either loop (--no-pm-qos; cyclictest --laptop)");
  hal::RtConfig process;
  process.lock_memory = true;
  process.prefault_stack_bytes = 0;
  const hal::RtReport locked = hal::apply_rt_config(process);
  locked.print(stdout);
  g_ours.reset();
  // Init: the simulated robot, the master brought up, the handler (as bench fig4 sets them up).
  static TaskLinks links;
  static SelectedNic selected;
  const Status opened = selected.open(NicChoice{});
  if (!opened.ok()) return fail("bench", "cannot open the simulated robot", opened.error());
  static StartUpSlot<drivers::JointBus> bus_slot;  // not in every command's image (start_up_slot.hpp)
  if (!bus_slot.reserve()) return fail("bench", "not enough memory for the bus");
  drivers::JointBus& bus = bus_slot.emplace(*selected.nic());
  const Status up = bus.bring_up(ecat::MasterOptions{});
  if (!up.ok()) return fail("bench", "bring-up failed", up.error());
  static TaskPorts task_ports(links);  // as `run` wires the tasks (runtime/task_ports.hpp)
  static EthercatHandler handler(bus, task_ports.ethercat_handler(), 0);
  hal::RtReport report;
  hal::RtReport reference_report;
  static Interleaving shared;
  g_reference.reset();
  std::thread reference(reference_loop, std::ref(shared), std::ref(selected.nic()->clock()), cpu, &setup, &reference_report);
  std::thread loop(our_loop, std::ref(handler), std::ref(selected.nic()->clock()), periods, cpu, &setup, &shared, &report);
  loop.join();
  shared.stop.store(true, std::memory_order_release);  // also when our loop gave up before OP
  reference.join();
  report.print(stdout);
  if (!reference_report.fully_applied()) {
    (void)std::printf("reference loop's real-time set-up not fully applied:\n");
    reference_report.print(stdout);
  }
  if (setup.failed) return fail("bench", "the network did not reach OP");
  (void)std::printf("heap_allocations_in_loop: %" PRIu64 " allocations\n", setup.heap_allocations);

  const Figures ours = figures_of(g_ours);
  print_figures("ours", ours);

  const Figures interleaved = figures_of(g_reference);
  (void)std::printf("reference: cyclictest's loop (sleep to an absolute release, read the clock, no work) in a second thread "
                    "on the same CPU at the same priority, released half a period after each of ours, in the same run\n");
  print_figures("reference", interleaved);
  (void)std::printf("reference_skipped: %" PRIu64 " periods (released while our cycle ran: they would time our work)\n",
                    shared.skipped);
  (void)std::printf("ratio_interleaved_p50: %.2f ours/reference\n", ratio(ours.p50_ns, interleaved.p50_ns));
  (void)std::printf("ratio_interleaved_p99: %.2f ours/reference\n", ratio(ours.p99_ns, interleaved.p99_ns));

  Figures floor;
  char why[160] = "";
  if (!run_cyclictest(periods, cpu, setup.pm_qos, floor, why, sizeof why)) {
    (void)std::printf("cyclictest: not measured: %s\n", why);
    return fail("bench", "cyclictest did not run: no ratio");
  }
  print_figures("cyclictest", floor);
  (void)std::printf("cyclictest_resolution: 1000 ns (its histogram's bucket)\n");
  // cyclictest truncates each sample to whole microseconds (13.9 us counts as 13), so ours are
  // truncated the same way before the ratio: a percentile of truncated samples is the truncated
  // percentile. Untruncated, a loop as fast as cyclictest's reads about 1.05 at a 14 us median.
  (void)std::printf("ratio_p50: %.2f ours/cyclictest (ours truncated to whole us, as cyclictest records)\n",
                    ratio(whole_us(ours.p50_ns), floor.p50_ns));
  (void)std::printf("ratio_p99: %.2f ours/cyclictest (ours truncated to whole us)\n", ratio(whole_us(ours.p99_ns), floor.p99_ns));
  (void)std::printf("ratio_max: %.2f ours/cyclictest (ours truncated to whole us)\n", ratio(whole_us(ours.max_ns), floor.max_ns));
  return 0;
}

}  // namespace rescue::app
