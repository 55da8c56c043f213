#include "core/app/bench/bench_fig4.hpp"

#include <dirent.h>
#include <pthread.h>
#include <sched.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <cerrno>
#include <atomic>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <thread>

#include "core/app/bench/bench_files.hpp"
#include "core/app/bench/bench_header.hpp"
#include "core/app/bench/timed_nic.hpp"
#include "core/app/config/firmware_config.hpp"
#include "core/app/config/task_table.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/runtime/task_ports.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/replay_window.hpp"
#include "core/app/runtime/nic_factory.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "core/kinematics/rc_period.hpp"
#include "core/kinematics/rescue_motion.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/memory/start_up_slot.hpp"
#include "core/timing/period_recorder.hpp"
#include "drivers/joint/joint_bus.hpp"
#include "hal/files/trusted_file.hpp"
#include "hal/net/udp_socket.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/clock.hpp"
#include "hal/time/tsc_timer.hpp"
#include "hal/time/wall_clock.hpp"

extern char** environ;  // NOLINT(readability-redundant-declaration): posix_spawn passes it on

namespace rescue::app {
namespace {

constexpr std::int64_t kDefaultPeriods = 5000;  // 5 s per case
constexpr std::int64_t kMaxPeriods = 60000;     // per case: the series' fixed capacity
constexpr int kCases = 2;
constexpr int kTasks = 2;
constexpr const char* kCaseNames[kCases] = {"without_affinity", "with_affinity"};
constexpr const char* kTaskNames[kTasks] = {"ethercat", "rc"};
constexpr int kEthercat = 0;
constexpr int kRc = 1;
constexpr int kMaxPeriodsToOp = 5000;
constexpr int kUdpPerSecond = 2000;
constexpr hal::Nanoseconds kPeriod = config::kRcTaskPeriodNs;
static_assert(config::kRcTaskPeriodNs == config::kEthercatHandlerPeriodNs, "Fig. 4: both tasks at 1 kHz");

// The handler's period split in three (the EtherCAT handler only; 0 for the RC task): its own work
// (the paper's Fig. 4 figure: the handler alone), the in-process simulator's share (SimulatedNic::send
// runs the segment) and the wait for the frame's modelled return (SimulatedNic::receive).
enum Part : int { kHandlerOnly = 0, kSimulator = 1, kFrameWait = 2, kParts = 3 };
constexpr const char* kPartNames[kParts] = {"handler_only", "simulator", "frame_wait"};

struct Series {
  std::array<std::uint32_t, kMaxPeriods> execution_ns{};
  std::array<std::uint32_t, kMaxPeriods> latency_ns{};
  std::array<std::array<std::uint32_t, kParts>, kMaxPeriods> part_ns{};
  std::int64_t count{0};
};

// The series (about 4.8 MB): reserved and built when the bench starts, after mlockall, so locked
// and populated before the measurement (StartUpSlot: not in every command's image, `run`'s included).
struct SeriesTable {
  Series at[kTasks][kCases];
};
StartUpSlot<SeriesTable> g_series_slot;
SeriesTable* g_series = nullptr;
// Static storage: touched once before the measurement (prefaulted by mlockall), never allocated.
PeriodRecorder g_recorders[kTasks][kCases];
LatencyHistogram g_parts[kCases][kParts];  // the handler's split, per case
TaskLinks g_links;
char g_names[kTasks][kCases][40];

struct Shared {
  std::int64_t periods{0};
  hal::TscTimer timer = hal::TscTimer::monotonic_fallback("not calibrated yet");
  std::atomic<int> ready{0};        // task threads past their set-up (the handler: in OP)
  std::atomic<bool> go{false};      // measurement starts
  std::atomic<int> phase{-1};       // the case the handler thread is in (-1: before, kCases: done)
  std::atomic<bool> stop{false};    // helper threads end
  std::atomic<bool> failed{false};  // a task could not start (the handler did not reach OP)
  hal::RtReport rt[kTasks][kCases]{};
};
Shared g_shared;

std::uint32_t clamp_u32(std::int64_t v) noexcept {
  if (v < 0) return 0;
  return v > 0xFFFFFFFFLL ? 0xFFFFFFFFU : static_cast<std::uint32_t>(v);
}

// Pins the calling thread to `cpu`, or lets it run on every online CPU when cpu < 0.
bool set_affinity(int cpu) noexcept {
  cpu_set_t set;
  CPU_ZERO(&set);
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  for (long c = 0; c < online && c < CPU_SETSIZE; ++c) {
    if (cpu < 0 || c == cpu) CPU_SET(static_cast<std::size_t>(c), &set);
  }
  return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
}

// The case's CPU of a Table I task on this machine; -1 (every CPU) without affinity.
int case_cpu(int which_case, TaskId task) noexcept {
  return which_case == 0 ? -1 : table_cpu_on_this_machine(task_spec(task).cpu);
}

void apply_task_rt(int task, TaskId id, int which_case) noexcept {
  hal::RtConfig rt;
  rt.lock_memory = false;  // once for the process
  rt.prefault_stack_bytes = which_case == 0 ? hal::kTaskStackPrefaultBytes : 0;
  rt.fifo_priority = task_spec(id).priority;
  rt.cpu = case_cpu(which_case, id);
  if (rt.cpu < 0) (void)set_affinity(-1);  // no pinning: every online CPU
  g_shared.rt[task][which_case] = hal::apply_rt_config(rt);
}

// `parts`: the handler's split in TSC ticks (nullptr for the RC task).
void record(int task, int which_case, std::int64_t latency_ns, std::uint64_t t0, std::uint64_t t1,
            const std::uint64_t* parts = nullptr) noexcept {
  g_recorders[task][which_case].record(latency_ns, t0, t1);
  Series& s = g_series->at[task][which_case];
  std::array<std::uint32_t, kParts> split{};
  if (parts != nullptr) {
    for (int p = 0; p < kParts; ++p) {
      split[static_cast<std::size_t>(p)] = clamp_u32(g_shared.timer.to_ns(parts[p]));
      g_parts[which_case][p].record(split[static_cast<std::size_t>(p)]);
    }
  }
  if (s.count < kMaxPeriods) {
    const auto k = static_cast<std::size_t>(s.count);
    s.execution_ns[k] = clamp_u32(g_shared.timer.to_ns(t1 - t0));
    s.latency_ns[k] = clamp_u32(latency_ns);
    s.part_ns[k] = split;
    ++s.count;
  }
}

// The EtherCAT handler: bring-up to OP, then periods until go, then kCases x N measured periods.
void handler_thread(EthercatHandler& handler, TimedNic& nic, hal::Clock& clock) noexcept {
  apply_task_rt(kEthercat, TaskId::ethercat_handler, 0);
  drivers::JointBus& bus = handler.bus();
  int to_op = 0;
  for (;;) {
    clock.sleep_until(bus.next_wakeup());
    const drivers::JointCycleResult r = handler.cycle();
    if (r.state == ecat::MasterState::op) break;
    if (++to_op == kMaxPeriodsToOp) {
      g_shared.failed.store(true);
      return;
    }
  }
  g_shared.ready.fetch_add(1);
  while (!g_shared.go.load(std::memory_order_acquire)) {
    clock.sleep_until(bus.next_wakeup());
    (void)handler.cycle();
  }
  for (int c = 0; c < kCases; ++c) {
    if (c > 0) apply_task_rt(kEthercat, TaskId::ethercat_handler, c);
    g_shared.phase.store(c, std::memory_order_release);
    for (std::int64_t i = 0; i < g_shared.periods; ++i) {
      const hal::Nanoseconds release = bus.next_wakeup();
      clock.sleep_until(release);
      const hal::Nanoseconds woke = clock.now();
      const std::uint64_t send_before = nic.send_ticks();
      const std::uint64_t receive_before = nic.receive_ticks();
      const std::uint64_t t0 = g_shared.timer.start();
      const drivers::JointCycleResult r = handler.cycle();
      const std::uint64_t t1 = g_shared.timer.stop();
      // cppcheck-suppress duplicateExpression ; cycle() went through the NIC: its ticks grew
      std::uint64_t parts[kParts] = {0, nic.send_ticks() - send_before, nic.receive_ticks() - receive_before};
      const std::uint64_t in_nic = parts[kSimulator] + parts[kFrameWait];
      parts[kHandlerOnly] = t1 - t0 > in_nic ? t1 - t0 - in_nic : 0;
      record(kEthercat, c, woke - release, t0, t1, parts);
      // Untimed, as in run's loop (task_loops.cpp), whose execution figure is the cycle alone too.
      handler.publish_figures(r, clock.now(), 0);
    }
  }
  g_shared.phase.store(kCases, std::memory_order_release);
  // Keep the network in OP until the RC thread is done too (a silent master trips the watchdogs).
  while (!g_shared.stop.load(std::memory_order_acquire)) {
    clock.sleep_until(bus.next_wakeup());
    (void)handler.cycle();
  }
}

// The RC task: the rescue motion, repeating, one RcPeriod per millisecond.
void rc_thread(kin::RcPeriod& rc) noexcept {
  apply_task_rt(kRc, TaskId::rc_tasks, 0);
  hal::MonotonicClock clock;
  const kin::JointVector teleop = kin::JointVector::Zero();
  const auto motion_periods = static_cast<std::int64_t>(rc.motion().duration_s() * 1000.0);
  std::int64_t k = 0;
  auto period = [&]() noexcept {
    const double t = static_cast<double>(k % (motion_periods > 0 ? motion_periods : 1)) * 0.001;
    ++k;
    return rc.run(t, 0, teleop);
  };
  (void)period();
  g_shared.ready.fetch_add(1);
  hal::Nanoseconds next = clock.now() + kPeriod;
  while (!g_shared.go.load(std::memory_order_acquire)) {
    clock.sleep_until(next);
    (void)period();
    next += kPeriod;
  }
  for (int c = 0; c < kCases; ++c) {
    if (c > 0) apply_task_rt(kRc, TaskId::rc_tasks, c);
    for (std::int64_t i = 0; i < g_shared.periods; ++i) {
      clock.sleep_until(next);
      const hal::Nanoseconds woke = clock.now();
      const std::uint64_t t0 = g_shared.timer.start();
      (void)period();
      const std::uint64_t t1 = g_shared.timer.stop();
      record(kRc, c, woke - next, t0, t1);
      next += kPeriod;
    }
  }
}

// The socket handler's thread: as runtime/task_loops.cpp's socket_task, following the handler's case.
void socket_thread(SocketHandler& socket) noexcept {
  hal::MonotonicClock clock;
  int pinned_for = -2;
  while (!g_shared.stop.load(std::memory_order_acquire)) {
    const int phase = g_shared.phase.load(std::memory_order_acquire);
    const int c = phase == 1 ? 1 : 0;
    if (c != pinned_for) {
      (void)set_affinity(case_cpu(c, TaskId::socket_handler));
      pinned_for = c;
    }
    socket.wait(5);
    socket.step(clock.now());
  }
}

std::uint64_t unix_ns() noexcept {
  timespec ts{};
  (void)clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1'000'000'000ULL + static_cast<std::uint64_t>(ts.tv_nsec);
}

// UDP load on the basic software CPU: three authenticated status queries, then one garbage datagram.
void udp_sender_thread(std::uint16_t port, const protocol::Key& key, std::uint64_t epoch) noexcept {
  (void)set_affinity(table_cpu_on_this_machine(task_spec(TaskId::basic_software).cpu));
  hal::UdpSocket out;
  if (!out.open("127.0.0.1", 0).ok()) return;
  const Result<std::uint32_t> loopback = hal::parse_ipv4("127.0.0.1");
  if (!loopback.ok()) return;
  hal::MonotonicClock clock;
  const hal::Nanoseconds gap = hal::kNsPerSec / kUdpPerSecond;
  hal::Nanoseconds next = clock.now();
  std::uint64_t sequence = 0;
  std::array<std::uint8_t, protocol::kMaxDatagram> bytes{};
  std::uint64_t n = 0;
  while (!g_shared.stop.load(std::memory_order_acquire)) {
    std::size_t size = 0;
    if (n % 4 == 3) {
      for (std::size_t i = 0; i < 48; ++i) bytes[i] = static_cast<std::uint8_t>(n * 31 + i * 7);
      size = 48;
    } else {
      protocol::Message m;
      m.header.type = protocol::MessageType::get_status;
      m.header.sender = 1;
      m.header.robot = protocol::kDefaultRobotId;
      m.header.epoch = epoch;
      const std::uint64_t now_ns = unix_ns();
      sequence = now_ns > sequence ? now_ns : sequence + 1;
      m.header.sequence = sequence;
      const Result<std::size_t> sealed = protocol::seal(m, key, ByteSpan(bytes));
      size = sealed.ok() ? sealed.value() : 0;
    }
    if (size > 0) (void)out.send_to(loopback.value(), port, ConstByteSpan(bytes.data(), size));
    ++n;
    next += gap;
    clock.sleep_until(next);
  }
}

// stress-ng --cpu 1 --vm 1 --vm-bytes 128M --taskset CPU --timeout S, or -1 when it cannot start.
pid_t start_stress(int cpu, std::int64_t seconds) noexcept {
  char taskset[16];
  char timeout[24];
  (void)std::snprintf(taskset, sizeof taskset, "%d", cpu);
  (void)std::snprintf(timeout, sizeof timeout, "%" PRId64 "s", seconds);
  char name[] = "stress-ng";
  char a_cpu[] = "--cpu";
  char a_one[] = "1";
  char a_vm[] = "--vm";
  char a_vm_one[] = "1";
  char a_bytes[] = "--vm-bytes";
  char a_bytes_v[] = "128M";
  char a_taskset[] = "--taskset";
  char a_timeout[] = "--timeout";
  char a_quiet[] = "--quiet";
  char* argv[] = {name, a_cpu, a_one, a_vm, a_vm_one, a_bytes, a_bytes_v, a_taskset, taskset, a_timeout, timeout, a_quiet, nullptr};
  pid_t pid = -1;
  if (posix_spawnp(&pid, "stress-ng", nullptr, nullptr, argv, environ) != 0) return -1;
  return pid;
}

void stop_child(pid_t pid) noexcept {
  if (pid <= 0) return;
  (void)::kill(pid, SIGTERM);
  int status = 0;
  (void)::waitpid(pid, &status, 0);
}

bool write_series(std::FILE* out, const void* /*unused*/) noexcept {
  // execution_ns is the whole period's work; for the handler it splits into handler_only_ns (the
  // handler alone: the paper's Fig. 4), simulator_ns and frame_wait_ns (0 for the RC task).
  bool ok = std::fprintf(out, "case,task,period,execution_ns,latency_ns,handler_only_ns,simulator_ns,frame_wait_ns\n") > 0;
  for (int c = 0; c < kCases; ++c) {
    for (int t = 0; t < kTasks; ++t) {
      const Series& s = g_series->at[t][c];
      for (std::int64_t i = 0; i < s.count; ++i) {
        const auto k = static_cast<std::size_t>(i);
        ok = std::fprintf(out, "%s,%s,%" PRId64 ",%u,%u,%u,%u,%u\n", kCaseNames[c], kTaskNames[t], i, s.execution_ns[k],
                          s.latency_ns[k], s.part_ns[k][kHandlerOnly], s.part_ns[k][kSimulator], s.part_ns[k][kFrameWait]) > 0 && ok;
      }
    }
  }
  return ok;
}

bool write_summary(std::FILE* out, const void* /*unused*/) noexcept {
  const PeriodRecorder* all[kTasks * kCases] = {&g_recorders[0][0], &g_recorders[1][0], &g_recorders[0][1],
                                                &g_recorders[1][1]};
  return PeriodRecorder::write_csv(out, Span<const PeriodRecorder* const>(all));
}

void print_figures(const char* key, const LatencyHistogram& h) noexcept {
  const PeriodFigures f = PeriodRecorder::figures(h);
  (void)std::printf("%s_min: %" PRIu64 " ns\n", key, f.summary.min);
  (void)std::printf("%s_mean: %.0f ns\n", key, f.summary.mean);
  (void)std::printf("%s_std: %.0f ns\n", key, f.summary.stddev);
  (void)std::printf("%s_max: %" PRIu64 " ns\n", key, f.summary.max);
  (void)std::printf("%s_p99.9: %" PRIu64 " ns\n", key, f.summary.p999);
}

// Other processes' real-time threads (SCHED_FIFO/RR, not kernel threads), by the CPU they last ran
// on: on a shared machine they compete with the pinned tasks (/proc/PID/task/TID/stat fields 39
// processor, 40 rt_priority, 41 policy; 4 ppid: kernel threads are children of kthreadd, pid 2).
void print_other_rt_threads(const char* when) noexcept {
  constexpr int kCpus = 64;
  int count[kCpus] = {};
  int top[kCpus] = {};
  const long self = ::getpid();
  DIR* proc = ::opendir("/proc");
  if (proc == nullptr) return;
  // readdir is unsafe only on a stream shared between threads; these two are this function's own.
  while (const dirent* p = ::readdir(proc)) {  // NOLINT(concurrency-mt-unsafe)
    char* end = nullptr;
    const long pid = std::strtol(p->d_name, &end, 10);
    if (end == p->d_name || *end != '\0' || pid == self || pid == 2) continue;
    char tasks_path[64];
    (void)std::snprintf(tasks_path, sizeof tasks_path, "/proc/%ld/task", pid);
    DIR* tasks = ::opendir(tasks_path);
    if (tasks == nullptr) continue;
    while (const dirent* t = ::readdir(tasks)) {  // NOLINT(concurrency-mt-unsafe): see above
      if (t->d_name[0] == '.') continue;
      char stat_path[320];
      (void)std::snprintf(stat_path, sizeof stat_path, "/proc/%ld/task/%s/stat", pid, t->d_name);
      std::FILE* f = std::fopen(stat_path, "r");
      if (f == nullptr) continue;
      char line[1024];
      const bool read = std::fgets(line, sizeof line, f) != nullptr;
      (void)std::fclose(f);
      const char* after = read ? std::strrchr(line, ')') : nullptr;
      if (after == nullptr) continue;
      // Fields from 3 on, after "pid (comm)".
      long field[42] = {};
      int n = 3;
      const char* at = after + 2;
      while (n < 42 && *at != '\0') {
        if (n != 3) field[n] = std::strtol(at, &end, 10);
        const char* space = std::strchr(at, ' ');
        if (space == nullptr) break;
        at = space + 1;
        ++n;
      }
      if (n < 41 || field[4] == 2) continue;  // short line, or a kernel thread
      const long policy = field[41];
      const long cpu = field[39];
      if ((policy == 1 || policy == 2) && cpu >= 0 && cpu < kCpus) {
        ++count[cpu];
        if (field[40] > top[cpu]) top[cpu] = static_cast<int>(field[40]);
      }
    }
    (void)::closedir(tasks);
  }
  (void)::closedir(proc);
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  for (long c = 0; c < online && c < kCpus; ++c) {
    (void)std::printf("other_rt_threads_%s_cpu%ld: %d threads (highest SCHED_FIFO/RR priority %d)\n", when, c, count[c],
                      top[c]);
  }
}

// The conditions the figure was measured under, for the PNG (a reader of the picture alone must
// know them): kernel and PREEMPT_RT, CPUs, whether the Table I affinity was applied, the load.
void describe_conditions(char* out, std::size_t size, const char* load, std::int64_t periods) noexcept {
  struct utsname host {};
  const char* release = ::uname(&host) == 0 ? host.release : "unknown";
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  bool applied = true;
  for (const auto& task : g_shared.rt) applied = applied && task[kCases - 1].fully_applied();  // the with-affinity case
  (void)std::snprintf(out, size,
                      "kernel %s, PREEMPT_RT %s, %ld CPUs online; Table I affinity %s%s; load: %s; %" PRId64
                      " periods per case; timer %s",
                      release, kernel_is_preempt_rt() ? "yes" : "no", online, applied ? "applied" : "refused in part",
                      online < 4 ? " but degraded (fewer than 4 CPUs: tasks share CPUs)" : "", load, periods,
                      hal::to_string(g_shared.timer.source()));
}

void print_machine() noexcept {
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  (void)std::printf("preempt_rt: %s\n", kernel_is_preempt_rt() ? "yes" : "no (stock kernel)");
  (void)std::printf("cpus_online: %ld\n", online);
  (void)std::printf("table_i_cpus: 4 hardware threads assumed (basic software 0, socket handler + message parser 1, "
                    "joint manager + RC tasks 2, EtherCAT handler 3)\n");
  for (const TaskId id : {TaskId::basic_software, TaskId::socket_handler, TaskId::rc_tasks, TaskId::ethercat_handler}) {
    const TaskSpec& t = task_spec(id);
    const int here = table_cpu_on_this_machine(t.cpu);
    (void)std::printf("affinity_mapping: %s: Table I CPU %d -> CPU %d%s\n", t.name, t.cpu, here,
                      here != t.cpu ? " (absent here: the last CPU)" : "");
  }
  if (online < 4) {
    (void)std::printf("affinity_degraded: yes: with %ld CPUs the EtherCAT handler, the RC task and the socket handler "
                      "share CPU %d; only the basic software CPU 0 (the load) is separated from them\n",
                      online, table_cpu_on_this_machine(task_spec(TaskId::ethercat_handler).cpu));
  }
}

// The report's figures: each task's real-time set-up per case, then its execution and wake-up figures.
void print_fig4_figures() noexcept {
  for (int c = 0; c < kCases; ++c) {
    for (int t = 0; t < kTasks; ++t) {
      (void)std::printf("rt_%s: %s\n", g_names[t][c], g_shared.rt[t][c].fully_applied() ? "applied" : "refused in part:");
      if (!g_shared.rt[t][c].fully_applied()) g_shared.rt[t][c].print(stdout);
    }
  }
  (void)std::printf("timer_source: %s\n", hal::to_string(g_shared.timer.source()));
  (void)std::printf("periods_per_case: %" PRId64 " periods\n", static_cast<std::int64_t>(g_shared.periods));
  for (int c = 0; c < kCases; ++c) {
    for (int t = 0; t < kTasks; ++t) {
      char key_name[192];  // a name of g_names and a suffix, with room for GCC's -Wformat-truncation bound
      (void)std::snprintf(key_name, sizeof key_name, "%s_execution", g_names[t][c]);
      print_figures(key_name, g_recorders[t][c].execution());
      (void)std::snprintf(key_name, sizeof key_name, "%s_wakeup_latency", g_names[t][c]);
      print_figures(key_name, g_recorders[t][c].latency());
      if (t != kEthercat) continue;
      // The handler's execution split: handler_only is the paper's Fig. 4 figure (docs/timing.md).
      for (int p = 0; p < kParts; ++p) {
        (void)std::snprintf(key_name, sizeof key_name, "%s_%s", g_names[t][c], kPartNames[p]);
        print_figures(key_name, g_parts[c][p]);
      }
    }
  }
}

// The CSV files into --out, then the PNG drawn by the plot script (nullptr: --no-plot) with the
// conditions it was measured under. 0, or the exit status.
int write_and_plot(const hal::OpenFile& out, const char* out_dir, const char* script, const char* load,
                   std::int64_t periods) noexcept {
  char csv[512];
  char summary[512];
  if (!write_file("fig4", out, out_dir, "fig4.csv", write_series, nullptr, csv, sizeof csv) ||
      !write_file("fig4", out, out_dir, "fig4-summary.csv", write_summary, nullptr, summary, sizeof summary)) {
    return fail("bench", "cannot write the CSV files into --out");
  }
  (void)std::printf("csv: %s\n", csv);
  (void)std::printf("summary_csv: %s\n", summary);
  if (script != nullptr) {
    char png[512];
    (void)std::snprintf(png, sizeof png, "%s/fig4.png", out_dir);
    char conditions[512];
    describe_conditions(conditions, sizeof conditions, load, periods);
    char* argv[] = {const_cast<char*>(script), csv, png, conditions, nullptr};  // NOLINT(cppcoreguidelines-pro-type-const-cast): argv is not written
    const int plotted = run_python(argv, nullptr);
    if (plotted != 0) {
      (void)std::fprintf(stderr, "rescue-motion bench: fig4: the plot script %s exited %d (its error above); the CSV files are written\n",
                         script, plotted);
      return 1;
    }
    (void)std::printf("png: %s\n", png);
  }
  return 0;
}

// Before measuring: the plot script and matplotlib (with --plot), and --out, created if needed and
// opened as a directory of our own (written through this descriptor only: a directory another user
// owns or may write, as the default under /tmp made by someone else, is refused). 0, or the exit status.
int check_prerequisites(const ParsedArgs& args, bool plot, const char* out_dir, char* script, std::size_t script_size,
                        Result<hal::OpenFile>& out) noexcept {
  char looked[1400];
  if (plot && !find_script(args.value("plot-script"), "plot_fig4.py", "toolchain/plot_fig4.py", script, script_size, looked, sizeof looked)) {
    (void)std::fprintf(stderr, "rescue-motion bench: fig4: no plot script (looked: %s); give --plot-script PATH or --no-plot\n",
                       looked);
    return 1;
  }
  if (plot && !python_imports("matplotlib")) {
    return fail("bench", "fig4: /usr/bin/python3 cannot import matplotlib (apt install python3-matplotlib), or --no-plot");
  }
  if (::mkdir(out_dir, 0755) != 0 && errno != EEXIST) return fail("bench", "cannot create the --out directory");
  // Checked before minutes of measuring, and written through this descriptor only: a directory
  // another user owns or may write (the default under /tmp, made by someone else) is refused.
  hal::FileProblem out_why;
  out = hal::open_trusted_directory(out_dir, hal::DirectoryUse::output, out_why);
  if (!out.ok()) {
    (void)std::fprintf(stderr, "rescue-motion bench: fig4: --out: %s\n", out_why.c_str());
    return 1;
  }
  return 0;
}

// The load beside the measured tasks (--load): stress-ng on the basic software CPU, said in the
// report with what was started; the UDP sender is started with the tasks. The stress-ng process, or -1.
pid_t start_load(const char* load, bool want_stress, bool want_udp, std::int64_t periods) noexcept {
  const int basic_cpu = table_cpu_on_this_machine(task_spec(TaskId::basic_software).cpu);
  const std::int64_t stress_seconds = 2 * periods / 1000 + 30;  // ends by itself if we die
  const pid_t stress = want_stress ? start_stress(basic_cpu, stress_seconds) : -1;
  (void)std::printf("load: %s\n", load);
  if (want_stress) {
    (void)std::printf("load_stress: %s\n", stress > 0 ? "stress-ng --cpu 1 --vm 1 --vm-bytes 128M on the basic software CPU"
                                                       : "stress-ng not started (not installed? toolchain/setup.sh)");
    (void)std::printf("load_stress_cpu: %d\n", basic_cpu);
  }
  if (want_udp) {
    (void)std::printf("load_udp: %d datagrams/s to the socket handler (3 of 4 authenticated status queries, 1 garbage)\n",
                      kUdpPerSecond);
  }
  return stress;
}

}  // namespace

int bench_fig4(const ParsedArgs& args) noexcept {
  const Result<std::int64_t> periods = args.integer("periods", kDefaultPeriods, 10, kMaxPeriods);
  if (!periods.ok()) return fail("bench", "--periods must be 10..60000", periods.error());
  const char* load = args.value("load") != nullptr ? args.value("load") : "stress,udp";
  const bool want_stress = std::strstr(load, "stress") != nullptr;
  const bool want_udp = std::strstr(load, "udp") != nullptr;
  if (!want_stress && !want_udp && std::strcmp(load, "none") != 0) {
    return fail("bench", "--load must be none, stress, udp or stress,udp");
  }
  const char* out_dir = args.value("out") != nullptr ? args.value("out") : "/tmp/rescue-fig4";
  const bool plot = !args.has("no-plot");
  // The plot's prerequisites and the output directory first, each failure with its own cause,
  // before minutes of measuring.
  char script[640];
  Result<hal::OpenFile> out = make_error(Errc::not_found, "not opened");
  const int ready = check_prerequisites(args, plot, out_dir, script, sizeof script, out);
  if (ready != 0) return ready;

  print_bench_header(stdout, "fig4");
  print_machine();
  g_shared.periods = periods.value();

  // ---- init: everything that may allocate, fault or block ----
  hal::RtConfig process;
  process.fifo_priority = 0;
  process.prefault_stack_bytes = hal::kTaskStackPrefaultBytes;
  const hal::RtReport locked = hal::apply_rt_config(process);
  static StartUpSlot<drivers::JointBus> bus_slot;
  if (!g_series_slot.reserve() || !bus_slot.reserve()) return fail("bench", "not enough memory for the series and the bus");
  g_series = &g_series_slot.emplace();
  g_shared.timer = hal::TscTimer::calibrate();
  const double ns_per_tick = 1.0 / g_shared.timer.ticks_per_ns();
  for (int t = 0; t < kTasks; ++t) {
    for (int c = 0; c < kCases; ++c) {
      (void)std::snprintf(g_names[t][c], sizeof g_names[t][c], "%s_%s", kTaskNames[t], kCaseNames[c]);
      g_recorders[t][c].configure(g_names[t][c], ns_per_tick);
      g_recorders[t][c].reset();
      g_series->at[t][c].count = 0;
    }
  }
  for (auto& parts : g_parts) {
    for (LatencyHistogram& part : parts) part.reset();
  }
  static SelectedNic selected;
  const Status opened = selected.open(NicChoice{});
  if (!opened.ok()) return fail("bench", "cannot open the simulated robot", opened.error());
  static TimedNic timed_nic(*selected.nic(), g_shared.timer);
  drivers::JointBus& bus = bus_slot.emplace(timed_nic);
  const Status up = bus.bring_up(ecat::MasterOptions{});
  if (!up.ok()) return fail("bench", "bring-up failed", up.error());
  static TaskPorts task_ports(g_links);  // as `run` wires the tasks (runtime/task_ports.hpp)
  static EthercatHandler handler(bus, task_ports.ethercat_handler(), 0);
  static kin::RcPeriod rc(kin::ready_posture());

  // The socket handler (real code) on a loopback port with a fresh key.
  protocol::Key key{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(i * 37 + 11);
  static protocol::ReplayWindow replay;
  static hal::SystemWallClock wall;
  replay.begin_epoch(protocol::new_epoch());
  static SocketHandler socket(task_ports.socket_handler(), key, replay, wall);
  SocketHandlerOptions socket_options;
  socket_options.listen = "127.0.0.1";
  socket_options.control_port = 0;
  socket_options.sensor_port = 0;
  if (want_udp) {
    const Status s = socket.open(socket_options);
    if (!s.ok()) return fail("bench", "cannot open the socket handler's ports", s.error());
  }

  const pid_t stress = start_load(load, want_stress, want_udp, periods.value());
  print_other_rt_threads("before");
  (void)std::fflush(stdout);

  std::thread handler_task(handler_thread, std::ref(handler), std::ref(timed_nic), std::ref(selected.nic()->clock()));
  std::thread rc_task(rc_thread, std::ref(rc));
  std::thread socket_task;
  std::thread sender;
  if (want_udp) {
    socket_task = std::thread(socket_thread, std::ref(socket));
    sender = std::thread(udp_sender_thread, socket.control_port(), key, replay.epoch());
  }
  while (g_shared.ready.load() < kTasks && !g_shared.failed.load()) {
    struct timespec ms{0, 1'000'000};
    (void)nanosleep(&ms, nullptr);
  }
  if (!g_shared.failed.load()) {
    declare_init_complete(HeapGuardMode::count);
    g_shared.go.store(true, std::memory_order_release);
  } else {
    g_shared.go.store(true, std::memory_order_release);  // the RC thread ends its periods
  }
  rc_task.join();
  while (!g_shared.failed.load() && g_shared.phase.load(std::memory_order_acquire) != kCases) {
    struct timespec ms{0, 1'000'000};
    (void)nanosleep(&ms, nullptr);
  }
  const HeapGuardCounters heap = heap_guard_counters();
  print_other_rt_threads("after");
  g_shared.stop.store(true, std::memory_order_release);
  handler_task.join();
  if (socket_task.joinable()) socket_task.join();
  if (sender.joinable()) sender.join();
  stop_child(stress);
  if (g_shared.failed.load()) return fail("bench", "the network did not reach OP");

  // ---- report ----
  locked.print(stdout);
  print_fig4_figures();
  if (want_udp) {
    const SocketCounters& counters = socket.counters();
    (void)std::printf("udp_datagrams: %" PRIu64 " datagrams\n", counters.datagrams);
    (void)std::printf("udp_accepted: %" PRIu64 " datagrams\n", counters.accepted);
  }
  (void)std::printf("heap_allocations_after_init: %" PRIu64 " allocations\n", heap.allocations);
  const int written = write_and_plot(out.value(), out_dir, plot ? script : nullptr, load, periods.value());
  if (written != 0) return written;
  return heap.allocations == 0 ? 0 : fail("bench", "heap allocation after init complete");
}

}  // namespace rescue::app
