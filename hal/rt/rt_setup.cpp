#include "hal/rt/rt_setup.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cinttypes>
#include <cstdint>

#include "core/base/sanitizers.hpp"

namespace rescue::hal {
namespace {

constexpr std::size_t kStackSafetyMargin = std::size_t{64} * 1024;  // left untouched below the prefault: guard, callees

std::uint32_t errno_detail(int error) noexcept { return static_cast<std::uint32_t>(error); }

// Touches every page of a `bytes` alloca block. noinline: the block is released when it returns,
// the pages stay mapped (and locked, after mlockall MCL_FUTURE).
__attribute__((noinline)) void touch_stack(std::size_t bytes, std::size_t page) noexcept {
  auto* block = static_cast<volatile unsigned char*>(__builtin_alloca(bytes));
  // From the top of the block down, the direction the stack grows.
  for (std::size_t offset = bytes; offset >= page; offset -= page) block[offset - 1] = 0;
  block[0] = 0;
}

// What is left of the calling thread's stack below this frame; 0 when the OS will not say.
std::size_t stack_left() noexcept {
  pthread_attr_t attr;
  if (pthread_getattr_np(pthread_self(), &attr) != 0) return 0;
  void* low = nullptr;
  std::size_t size = 0;
  const int rc = pthread_attr_getstack(&attr, &low, &size);
  (void)pthread_attr_destroy(&attr);
  if (rc != 0) return 0;
  const unsigned char marker = 0;
  const auto here = reinterpret_cast<std::uintptr_t>(&marker);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  const auto bottom = reinterpret_cast<std::uintptr_t>(low);    // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  return here > bottom ? static_cast<std::size_t>(here - bottom) : 0;
}

RtItemReport run_item(const char* item, std::int64_t parameter, Status status, const char* unit = "") noexcept {
  RtItemReport report;
  report.item = item;
  report.parameter = parameter;
  report.unit = unit;
  report.outcome = status.ok() ? RtOutcome::applied : RtOutcome::refused;
  if (!status.ok()) report.error = status.error();
  return report;
}

RtItemReport skipped_item(const char* item) noexcept {
  RtItemReport report;
  report.item = item;
  report.outcome = RtOutcome::skipped;
  return report;
}

PageFaults page_faults_of(int who) noexcept {
  rusage usage{};
  if (getrusage(who, &usage) != 0) return PageFaults{};
  return PageFaults{static_cast<std::uint64_t>(usage.ru_minflt), static_cast<std::uint64_t>(usage.ru_majflt)};
}

}  // namespace

Status lock_memory() noexcept {
  if (kSanitizerInterceptsMalloc) {
    return make_error(Errc::unsupported, "sanitizer build: its shadow memory must not be locked");
  }
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return Status::success();
  const int error = errno;
  switch (error) {
    case EPERM: return make_error(Errc::permission_denied, "needs CAP_IPC_LOCK or a non-zero RLIMIT_MEMLOCK");
    case ENOMEM:
      return make_error(Errc::capacity_exceeded, "process larger than RLIMIT_MEMLOCK (ulimit -l) without CAP_IPC_LOCK");
    case EAGAIN: return make_error(Errc::busy, "some memory could not be locked");
    default: return make_error(Errc::io_error, "mlockall failed (errno)", errno_detail(error));
  }
}

Status prefault_stack(std::size_t bytes) noexcept {
  if (bytes == 0) return Status::success();
  const long page_size = sysconf(_SC_PAGESIZE);
  if (page_size <= 0) return make_error(Errc::io_error, "page size unknown (errno)", errno_detail(errno));
  const std::size_t left = stack_left();
  if (left == 0) return make_error(Errc::unsupported, "thread stack bounds unknown");
  if (bytes > left || left - bytes < kStackSafetyMargin) {
    return make_error(Errc::out_of_range, "stack too small for the prefault (KiB asked, KiB left)",
                      static_cast<std::uint32_t>(bytes / 1024), static_cast<std::uint32_t>(left / 1024));
  }
  touch_stack(bytes, static_cast<std::size_t>(page_size));
  return Status::success();
}

Status set_fifo_priority(int priority) noexcept {
  const int min = sched_get_priority_min(SCHED_FIFO);
  const int max = sched_get_priority_max(SCHED_FIFO);
  if (priority < min || priority > max) {
    return make_error(Errc::invalid_argument, "SCHED_FIFO priority outside the OS range (min, max)",
                      static_cast<std::uint32_t>(min), static_cast<std::uint32_t>(max));
  }
  if (kSanitizerSpinsBySchedYield) {  // core/base/sanitizers.hpp: the whole process would hang
    return make_error(Errc::unsupported, kThreadSanitizer
                                             ? "ThreadSanitizer build: its spin locks livelock SCHED_FIFO threads sharing a CPU"
                                             : "AddressSanitizer build: its spin locks livelock SCHED_FIFO threads sharing a CPU");
  }
  sched_param param{};
  param.sched_priority = priority;
  const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);  // returns the errno
  switch (error) {
    case 0: return Status::success();
    case EPERM: return make_error(Errc::permission_denied, "needs CAP_SYS_NICE or RLIMIT_RTPRIO (ulimit -r) >= the priority");
    default: return make_error(Errc::io_error, "pthread_setschedparam failed (errno)", errno_detail(error));
  }
}

Status hold_cpu_wakeup_latency(int microseconds) noexcept {
  if (microseconds < 0) return make_error(Errc::invalid_argument, "negative wake-up latency");
  // One request per process, kept open: closing the file ends the request. Set up at init only, but
  // in threads mode by every task thread at once: the first descriptor published wins, without a lock.
  static std::atomic<int> held{-1};
  int fd = held.load(std::memory_order_acquire);
  if (fd < 0) {
    const int opened = ::open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
    if (opened < 0) {
      const int error = errno;
      if (error == EACCES || error == EPERM) return make_error(Errc::permission_denied, "/dev/cpu_dma_latency needs root");
      if (error == ENOENT) return make_error(Errc::not_found, "/dev/cpu_dma_latency absent (kernel without PM QoS)");
      return make_error(Errc::io_error, "open(/dev/cpu_dma_latency) failed (errno)", errno_detail(error));
    }
    int expected = -1;
    if (held.compare_exchange_strong(expected, opened, std::memory_order_acq_rel)) {
      fd = opened;
    } else {
      (void)::close(opened);  // another thread's request is the process's
      fd = expected;
    }
  }
  // The device takes a binary 32-bit value in microseconds.
  const std::int32_t value = microseconds;
  if (::write(fd, &value, sizeof value) != static_cast<ssize_t>(sizeof value)) {
    return make_error(Errc::io_error, "write(/dev/cpu_dma_latency) failed (errno)", errno_detail(errno));
  }
  return Status::success();
}

static Status set_timer_slack(unsigned long nanoseconds) noexcept {
  if (prctl(PR_SET_TIMERSLACK, nanoseconds, 0, 0, 0) != 0) {
    return make_error(Errc::io_error, "prctl(PR_SET_TIMERSLACK) failed (errno)", errno_detail(errno));
  }
  return Status::success();
}

Status pin_to_cpu(int cpu) noexcept {
  const long present = sysconf(_SC_NPROCESSORS_CONF);
  if (cpu < 0 || cpu >= CPU_SETSIZE || (present > 0 && cpu >= present)) {
    return make_error(Errc::out_of_range, "CPU not present (CPU, CPUs present)", static_cast<std::uint32_t>(cpu),
                      static_cast<std::uint32_t>(present));
  }
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(static_cast<std::size_t>(cpu), &set);
  const int error = pthread_setaffinity_np(pthread_self(), sizeof set, &set);  // returns the errno
  switch (error) {
    case 0: return Status::success();
    case EINVAL:
      return make_error(Errc::refused, "CPU not in this process's allowed set, cpuset or taskset (CPU)",
                        static_cast<std::uint32_t>(cpu));
    case EPERM: return make_error(Errc::permission_denied, "affinity change not permitted");
    default: return make_error(Errc::io_error, "pthread_setaffinity_np failed (errno)", errno_detail(error));
  }
}

Result<SchedulingState> save_scheduling() noexcept {
  SchedulingState state;
  sched_param param{};
  const int error = pthread_getschedparam(pthread_self(), &state.policy, &param);  // returns the errno
  if (error != 0) return make_error(Errc::io_error, "pthread_getschedparam failed (errno)", errno_detail(error));
  state.priority = param.sched_priority;
  CPU_ZERO(&state.cpus);
  const int cpus = pthread_getaffinity_np(pthread_self(), sizeof state.cpus, &state.cpus);
  if (cpus != 0) return make_error(Errc::io_error, "pthread_getaffinity_np failed (errno)", errno_detail(cpus));
  return state;
}

Status restore_scheduling(const SchedulingState& state) noexcept {
  sched_param param{};
  param.sched_priority = state.priority;
  const int error = pthread_setschedparam(pthread_self(), state.policy, &param);  // returns the errno
  if (error != 0) return make_error(Errc::io_error, "pthread_setschedparam failed (errno)", errno_detail(error));
  const int cpus = pthread_setaffinity_np(pthread_self(), sizeof state.cpus, &state.cpus);
  if (cpus != 0) return make_error(Errc::io_error, "pthread_setaffinity_np failed (errno)", errno_detail(cpus));
  return Status::success();
}

const char* to_string(RtOutcome outcome) noexcept {
  switch (outcome) {
    case RtOutcome::applied: return "applied";
    case RtOutcome::skipped: return "skipped";
    case RtOutcome::refused: return "refused";
  }
  return "unknown";
}

RtReport apply_rt_config(const RtConfig& config) noexcept {
  // Order: pin, then raise the priority (so the thread never runs at RT priority on the wrong CPU),
  // then lock, then prefault the stack (locked as it appears). Locking before the priority was
  // raised made a task's start-up wait behind its siblings': mlockall populates every page of the
  // process (tens of MiB, its thread stacks included), and five task processes forked at once did
  // it together on one CPU, 12-140 ms for the EtherCAT handler (docs/timing.md "Time to OP").
  // The items keep their places in the report.
  static constexpr const char* kMemory = "memory lock (mlockall current+future)";
  static constexpr const char* kCpu = "CPU affinity";
  static constexpr const char* kFifo = "SCHED_FIFO priority";
  static constexpr const char* kStack = "stack prefault";
  static constexpr const char* kSlack = "timer slack";
  static constexpr const char* kWake = "CPU wake-up latency (PM QoS, /dev/cpu_dma_latency)";
  RtReport report;
  report.items[1] = config.cpu >= 0 ? run_item(kCpu, config.cpu, pin_to_cpu(config.cpu)) : skipped_item(kCpu);
  report.items[2] =
      config.fifo_priority != 0 ? run_item(kFifo, config.fifo_priority, set_fifo_priority(config.fifo_priority)) : skipped_item(kFifo);
  report.items[0] = config.lock_memory ? run_item(kMemory, -1, lock_memory()) : skipped_item(kMemory);
  report.items[3] = config.prefault_stack_bytes != 0
                        ? run_item(kStack, static_cast<std::int64_t>(config.prefault_stack_bytes / 1024),
                                   prefault_stack(config.prefault_stack_bytes), " KiB")
                        : skipped_item(kStack);
  report.items[4] = config.timer_slack_ns != 0
                        ? run_item(kSlack, static_cast<std::int64_t>(config.timer_slack_ns), set_timer_slack(config.timer_slack_ns), " ns")
                        : skipped_item(kSlack);
  report.items[5] = config.cpu_wakeup_latency_us >= 0
                        ? run_item(kWake, config.cpu_wakeup_latency_us, hold_cpu_wakeup_latency(config.cpu_wakeup_latency_us), " us")
                        : skipped_item(kWake);
  return report;
}

bool RtReport::fully_applied() const noexcept { return refused_count() == 0; }

std::size_t RtReport::refused_count() const noexcept {
  return static_cast<std::size_t>(
      std::count_if(items.begin(), items.end(), [](const RtItemReport& item) { return item.outcome == RtOutcome::refused; }));
}

std::size_t RtReport::format_item(const RtItemReport& item, char* buffer, std::size_t size) noexcept {
  char parameter[32] = "";
  if (item.parameter >= 0) (void)std::snprintf(parameter, sizeof parameter, " %" PRId64 "%s", item.parameter, item.unit);
  // The numbers the reason names in parentheses, e.g. "CPU not present (CPU, CPUs present) = 7, 4".
  char details[48] = "";
  if (item.error.detail1 != 0) {
    (void)std::snprintf(details, sizeof details, " = %u, %u", item.error.detail0, item.error.detail1);
  } else if (item.error.detail0 != 0) {
    (void)std::snprintf(details, sizeof details, " = %u", item.error.detail0);
  }
  int length = 0;
  if (item.outcome == RtOutcome::refused) {
    length = std::snprintf(buffer, size, "rt: %s%s: refused (%s: %s%s)", item.item, parameter, to_string(item.error.code),
                           item.error.what, details);
  } else if (item.outcome == RtOutcome::skipped) {
    length = std::snprintf(buffer, size, "rt: %s%s: skipped (not requested)", item.item, parameter);
  } else {
    length = std::snprintf(buffer, size, "rt: %s%s: applied", item.item, parameter);
  }
  if (length < 0 || size == 0) return 0;
  return static_cast<std::size_t>(length) < size ? static_cast<std::size_t>(length) : size - 1;
}

void RtReport::print(std::FILE* out) const noexcept {
  for (const RtItemReport& item : items) {
    char line[256];
    (void)format_item(item, line, sizeof line);
    std::fprintf(out, "%s\n", line);
  }
  if (!fully_applied()) {
    std::fprintf(out, "rt: DEGRADED: %zu of %zu real-time settings refused; timing figures are not real-time\n",
                 refused_count(), items.size());
  }
}

PageFaults page_faults_of_process() noexcept { return page_faults_of(RUSAGE_SELF); }
PageFaults page_faults_of_thread() noexcept { return page_faults_of(RUSAGE_THREAD); }

Status name_this_thread(const char* name) noexcept {
  if (name == nullptr || name[0] == '\0') return make_error(Errc::invalid_argument, "empty thread name");
  if (::prctl(PR_SET_NAME, name, 0, 0, 0) != 0) {
    return make_error(Errc::io_error, "prctl PR_SET_NAME refused", static_cast<std::uint32_t>(errno));
  }
  return Status::success();
}

ThreadSchedule thread_schedule() noexcept {
  ThreadSchedule s;
  s.policy = ::sched_getscheduler(0);
  sched_param param{};
  if (::sched_getparam(0, &param) == 0) s.priority = param.sched_priority;
  s.cpu = ::sched_getcpu();
  return s;
}

const char* policy_name(int policy) noexcept {
  switch (policy) {
    case SCHED_OTHER: return "OTHER";
    case SCHED_FIFO: return "FIFO";
    case SCHED_RR: return "RR";
    case SCHED_BATCH: return "BATCH";
    case SCHED_IDLE: return "IDLE";
#ifdef SCHED_DEADLINE
    case SCHED_DEADLINE: return "DEADLINE";
#endif
    default: return "?";
  }
}

}  // namespace rescue::hal
