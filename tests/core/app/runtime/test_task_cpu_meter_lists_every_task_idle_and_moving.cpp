// The per-task CPU meter of `run`'s summary (runtime/task_cpu.hpp) lists every thread of the
// processes it is given by its task name, with the CPU it used per second of wall time, in the idle
// phase and in the moving phase; a thread that ended between two readings does not break a reading.
// CPU amounts are the kernel's; the test asserts only which rows there are and that a busy thread's
// share is not 0.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <unistd.h>

#include "core/app/runtime/task_cpu.hpp"
#include "core/memory/heap_guard.hpp"
#include "hal/rt/rt_setup.hpp"

namespace rescue::app {
namespace {

std::string printed(const TaskCpuMeter& meter) {
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  meter.print(out);
  (void)std::fclose(out);
  std::string result(text, size);
  std::free(text);
  return result;
}

// A named thread that works until told to stop (busy) or just waits (idle).
class NamedThread {
 public:
  NamedThread(const char* name, bool busy)
      : thread_([this, name, busy] {
          (void)hal::name_this_thread(name);
          started_.store(true);
          volatile std::uint64_t sink = 0;
          while (!stop_.load()) {
            if (busy) {
              for (int i = 0; i < 10000; ++i) sink = sink + static_cast<std::uint64_t>(i);
            } else {
              std::this_thread::sleep_for(std::chrono::milliseconds(1));
            }
          }
        }) {
    while (!started_.load()) std::this_thread::yield();
  }
  ~NamedThread() {
    stop_.store(true);
    thread_.join();
  }
  NamedThread(const NamedThread&) = delete;
  NamedThread& operator=(const NamedThread&) = delete;

 private:
  std::atomic<bool> started_{false};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST(TaskCpuMeter, ListsEveryThreadByNameInBothPhases) {
  NamedThread handler("ethercat", true);
  NamedThread manager("joint-manager", false);
  const int pids[] = {static_cast<int>(::getpid()), static_cast<int>(::getpid())};  // duplicates read once
  hal::VirtualClock clock(1'000'000'000);
  TaskCpuMeter meter;
  meter.observe(Span<const int>(pids, 2), clock, false, false);  // idle starts
  std::this_thread::sleep_for(std::chrono::milliseconds(60));
  clock.advance(kTaskCpuSampleEvery);
  meter.observe(Span<const int>(pids, 2), clock, true, false);  // the motion starts
  std::this_thread::sleep_for(std::chrono::milliseconds(60));
  clock.advance(kTaskCpuSampleEvery);
  meter.observe(Span<const int>(pids, 2), clock, true, false);
  meter.observe(Span<const int>(pids, 2), clock, true, true);  // the handler ended: no further reading
  clock.advance(kTaskCpuSampleEvery);
  meter.observe(Span<const int>(pids, 2), clock, true, false);

  const std::string text = printed(meter);
  for (const char* phase : {"idle", "moving"}) {
    for (const char* task : {"ethercat", "joint_manager"}) {
      EXPECT_NE(text.find(std::string("cpu_ms_per_s_") + phase + "_" + task + ": "), std::string::npos) << text;
    }
    EXPECT_NE(text.find(std::string("cpu_ms_per_s_") + phase + "_total: "), std::string::npos) << text;
    EXPECT_NE(text.find(std::string("wall_s_") + phase + ": 0.100"), std::string::npos) << text;
  }
  EXPECT_EQ(text.find("cpu_ms_per_s_moving_ethercat: 0.00\n"), std::string::npos) << "a busy thread used CPU\n" << text;
}

TEST(TaskCpuMeter, AProcessThatIsGoneIsCountedUnreadNotFatal) {
  const int pids[] = {static_cast<int>(::getpid()), 0x7ffffff0};  // the second pid does not exist
  const TaskCpuSample sample = read_task_cpu(Span<const int>(pids, 2), 5);
  EXPECT_GE(sample.count, 1U);
  EXPECT_GE(sample.unread, 1U);
  EXPECT_EQ(sample.at, 5);
}

// The meter reads after init, in the logger's or supervisor's loop, where the heap guard counts.
TEST(TaskCpuMeter, ReadsWithoutHeap) {
  NamedThread handler("ethercat", false);
  const int pids[] = {static_cast<int>(::getpid())};
  hal::VirtualClock clock(1'000'000'000);
  static TaskCpuMeter meter;
  declare_init_complete(HeapGuardMode::count);
  const std::uint64_t before = heap_guard_counters().allocations;
  meter.observe(Span<const int>(pids, 1), clock, false, false);
  clock.advance(kTaskCpuSampleEvery);
  meter.observe(Span<const int>(pids, 1), clock, true, false);
  const TaskCpuSample sample = read_task_cpu(Span<const int>(pids, 1), clock.now());
  const std::uint64_t after = heap_guard_counters().allocations;
  EXPECT_EQ(after - before, 0U);
  EXPECT_NE(sample.find("ethercat"), kTaskCpuMaxThreads);
}

}  // namespace
}  // namespace rescue::app
