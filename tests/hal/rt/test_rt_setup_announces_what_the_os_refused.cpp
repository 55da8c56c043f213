// Real-time set-up: every item is applied or refused with a reason, the report prints one line per
// item and a DEGRADED line when anything was refused. Anything that changes the process (mlockall,
// SCHED_FIFO, affinity, dropping privileges) runs in a forked child or a scratch thread.
#include <gtest/gtest.h>

#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "core/base/sanitizers.hpp"
#include "hal/rt/rt_setup.hpp"
#include "tests/support/forked_child.hpp"

namespace rescue::hal {
namespace {

// A CPU this process may run on.
int allowed_cpu() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 0;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (CPU_ISSET(cpu, &set)) return cpu;
  }
  return 0;
}

// Runs apply_rt_config in a forked child (optionally unprivileged first) and returns its report.
// Item names and reasons are static strings: after fork they are at the same addresses here.
struct ChildReport {
  RtReport report;
  bool dropped_privileges{false};
  bool ok{false};
};

ChildReport apply_in_child(const RtConfig& config, bool drop_privileges) {
  ChildReport result;
  int fds[2];
  if (pipe(fds) != 0) return result;
  const int status = test::run_in_child([&] {
    close(fds[0]);
    ChildReport mine;
    if (drop_privileges) {
      const rlimit zero{0, 0};
      (void)setrlimit(RLIMIT_RTPRIO, &zero);
      (void)setrlimit(RLIMIT_MEMLOCK, &zero);
      if (geteuid() == 0) {
        // nobody: losing uid 0 drops every capability (CAP_SYS_NICE, CAP_IPC_LOCK).
        if (setresgid(65534, 65534, 65534) != 0 || setresuid(65534, 65534, 65534) != 0) return 3;
      }
      mine.dropped_privileges = geteuid() != 0;
    }
    mine.report = apply_rt_config(config);
    mine.ok = true;
    return write(fds[1], &mine, sizeof mine) == static_cast<ssize_t>(sizeof mine) ? 0 : 4;
  });
  close(fds[1]);
  if (status == 0 && read(fds[0], &result, sizeof result) != static_cast<ssize_t>(sizeof result)) result.ok = false;
  close(fds[0]);
  return result;
}

std::string printed(const RtReport& report) {
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  report.print(out);
  std::fclose(out);
  std::string result(text, size);
  std::free(text);
  return result;
}

TEST(RtSetup, UnprivilegedProcessGetsEveryRefusalAnnounced) {
  RtConfig config;
  config.lock_memory = true;
  config.cpu = CPU_SETSIZE - 1;                 // not present on any test machine
  config.fifo_priority = 50;
  config.prefault_stack_bytes = std::size_t{1} << 40;  // far beyond any stack
  config.timer_slack_ns = 1;                     // any thread may set its own
  config.cpu_wakeup_latency_us = 0;              // /dev/cpu_dma_latency: root only
  const ChildReport child = apply_in_child(config, true);
  ASSERT_TRUE(child.ok) << "the child could not run or report";
  ASSERT_TRUE(child.dropped_privileges) << "could not become an unprivileged user";
  const RtReport& r = child.report;

  EXPECT_EQ(r.items[0].outcome, RtOutcome::refused);
  EXPECT_EQ(r.items[0].error.code, kSanitizerInterceptsMalloc ? Errc::unsupported : Errc::permission_denied);
  EXPECT_EQ(r.items[1].outcome, RtOutcome::refused);
  EXPECT_EQ(r.items[1].error.code, Errc::out_of_range);
  EXPECT_EQ(r.items[2].outcome, RtOutcome::refused);
  // Sanitizer builds whose spin locks livelock SCHED_FIFO refuse it before asking the kernel.
  EXPECT_EQ(r.items[2].error.code, kSanitizerSpinsBySchedYield ? Errc::unsupported : Errc::permission_denied);
  EXPECT_EQ(r.items[3].outcome, RtOutcome::refused);
  EXPECT_EQ(r.items[3].error.code, Errc::out_of_range);
  EXPECT_EQ(r.items[4].outcome, RtOutcome::applied);
  EXPECT_EQ(r.items[5].outcome, RtOutcome::refused);
  EXPECT_EQ(r.items[5].error.code, Errc::permission_denied);
  EXPECT_EQ(r.refused_count(), 5u);

  const std::string text = printed(r);
  EXPECT_NE(text.find(kSanitizerSpinsBySchedYield ? "rt: SCHED_FIFO priority 50: refused (unsupported: "
                                                   : "rt: SCHED_FIFO priority 50: refused (permission denied: needs CAP_SYS_NICE"),
            std::string::npos) << text;
  const std::string cpu_line = "rt: CPU affinity 1023: refused (out of range: CPU not present (CPU, CPUs present) = 1023, " +
                               std::to_string(sysconf(_SC_NPROCESSORS_CONF)) + ")\n";
  EXPECT_NE(text.find(cpu_line), std::string::npos) << text;
  EXPECT_NE(text.find("rt: DEGRADED: 5 of 6 real-time settings refused"), std::string::npos) << text;
}

TEST(RtSetup, EveryItemIsAppliedOrRefusedWithAReason) {
  RtConfig config;
  config.lock_memory = true;
  config.cpu = allowed_cpu();
  config.fifo_priority = 10;
  config.prefault_stack_bytes = 256 * 1024;
  config.timer_slack_ns = 1;
  config.cpu_wakeup_latency_us = 0;
  const ChildReport child = apply_in_child(config, false);
  ASSERT_TRUE(child.ok);
  const RtReport& r = child.report;
  for (const RtItemReport& item : r.items) {
    EXPECT_NE(item.outcome, RtOutcome::skipped) << item.item;
    if (item.outcome == RtOutcome::refused) {
      EXPECT_NE(item.error.code, Errc::ok) << item.item;
      EXPECT_GT(std::strlen(item.error.what), 0u) << item.item;
    }
  }
  EXPECT_EQ(r.items[1].outcome, RtOutcome::applied) << "pinning to an allowed CPU";
  EXPECT_EQ(r.items[3].outcome, RtOutcome::applied) << "prefaulting 256 KiB of an 8 MiB stack";
  const std::string text = printed(r);
  EXPECT_NE(text.find("rt: stack prefault 256 KiB: applied\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("DEGRADED") != std::string::npos, !r.fully_applied()) << text;
  RecordProperty("report", text);
}

TEST(RtSetup, NothingRequestedMeansEverythingSkipped) {
  RtConfig config;
  config.lock_memory = false;
  config.prefault_stack_bytes = 0;
  const RtReport r = apply_rt_config(config);  // changes nothing: safe in the test process
  for (const RtItemReport& item : r.items) EXPECT_EQ(item.outcome, RtOutcome::skipped) << item.item;
  EXPECT_TRUE(r.fully_applied());
  const std::string text = printed(r);
  EXPECT_NE(text.find("rt: SCHED_FIFO priority: skipped (not requested)\n"), std::string::npos) << text;
}

TEST(RtSetup, PriorityOutsideTheOsRangeIsAnInvalidArgument) {
  EXPECT_EQ(set_fifo_priority(0).error().code, Errc::invalid_argument);
  EXPECT_EQ(set_fifo_priority(100).error().code, Errc::invalid_argument);
}

TEST(RtSetup, PinningAndPrefaultOnAScratchThread) {
  Status pinned = make_error(Errc::busy, "not run");
  Status absent = Status::success();
  Status small = make_error(Errc::busy, "not run");
  Status huge = Status::success();
  std::thread scratch([&] {
    pinned = pin_to_cpu(allowed_cpu());
    absent = pin_to_cpu(-1);
    small = prefault_stack(64 * 1024);
    huge = prefault_stack(std::size_t{1} << 40);
  });
  scratch.join();
  EXPECT_TRUE(pinned.ok()) << pinned.error().what;
  EXPECT_EQ(absent.error().code, Errc::out_of_range);
  EXPECT_TRUE(small.ok()) << small.error().what;
  EXPECT_EQ(huge.error().code, Errc::out_of_range);
}

TEST(RtSetup, SingleLineFormatFitsTheBuffer) {
  RtItemReport item;
  item.item = "CPU affinity";
  item.parameter = 3;
  item.outcome = RtOutcome::refused;
  item.error = make_error(Errc::out_of_range, "CPU not present (CPU, CPUs present)");
  char small[16];
  const std::size_t length = RtReport::format_item(item, small, sizeof small);
  EXPECT_EQ(length, sizeof small - 1);
  EXPECT_STREQ(small, "rt: CPU affinit");
}

}  // namespace
}  // namespace rescue::hal
