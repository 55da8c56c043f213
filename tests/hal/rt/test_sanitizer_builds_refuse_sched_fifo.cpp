// A ThreadSanitizer or AddressSanitizer build refuses SCHED_FIFO, with its reason, and leaves the
// thread at normal priority: both runtimes wait for their own spin locks by sched_yield
// (sanitizer_common's StaticSpinMutex), so a SCHED_FIFO thread spinning on one held by a
// lower-priority thread on its CPU hangs the process (docs/build.md, `tsan` and `asan`). Labelled
// `concurrency`, so the tsan stage runs it; the asan stage runs every test; in the other builds it
// checks that the refusal stays out of them.
#include <gtest/gtest.h>

#include <sched.h>

#include <cstring>
#include <thread>

#include "core/base/sanitizers.hpp"
#include "hal/rt/rt_setup.hpp"

// Defined by each sanitizer's runtime only: which one this process runs under, found independently
// of the compile-time tests in core/base/sanitizers.hpp that the firmware uses.
extern "C" void __tsan_init() __attribute__((weak));  // NOLINT(bugprone-reserved-identifier)
extern "C" void __asan_init() __attribute__((weak));  // NOLINT(bugprone-reserved-identifier)

namespace rescue::hal {
namespace {

bool tsan_runtime_present() { return &__tsan_init != nullptr; }
bool asan_runtime_present() { return &__asan_init != nullptr; }

TEST(SanitizerBuilds, RefuseSchedFifoWithTheirReasonAndLeaveTheThreadAtNormalPriority) {
  ASSERT_EQ(kThreadSanitizer, tsan_runtime_present()) << "sanitizers.hpp misreads this build";
  ASSERT_EQ(kAddressSanitizer, asan_runtime_present()) << "sanitizers.hpp misreads this build";
  // A bad priority is a bad argument in every build, before any refusal.
  EXPECT_EQ(set_fifo_priority(0).error().code, Errc::invalid_argument);
  // A scratch thread: a priority applied in another build ends with it.
  std::thread scratch([] {
    const Status set = set_fifo_priority(80);
    if (tsan_runtime_present() || asan_runtime_present()) {
      ASSERT_FALSE(set.ok());
      EXPECT_EQ(set.error().code, Errc::unsupported);
      EXPECT_NE(std::strstr(set.error().what, tsan_runtime_present() ? "ThreadSanitizer build" : "AddressSanitizer build"), nullptr)
          << set.error().what;
      EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
    } else if (!set.ok()) {
      EXPECT_EQ(set.error().code, Errc::permission_denied) << set.error().what;  // only for want of privileges
    } else {
      EXPECT_EQ(sched_getscheduler(0), SCHED_FIFO);
    }
  });
  scratch.join();
}

}  // namespace
}  // namespace rescue::hal
