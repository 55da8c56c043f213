// A ThreadSanitizer build refuses SCHED_FIFO, with its reason, and leaves the thread at normal
// priority: TSan's runtime waits for its own spin locks by sched_yield (StaticSpinMutex), so a
// SCHED_FIFO thread spinning on one held by a lower-priority thread on its CPU hangs the process
// (docs/build.md, `tsan`). Labelled `concurrency`, so the tsan stage runs it; in the other builds it
// checks that the refusal stays out of them.
#include <gtest/gtest.h>

#include <sched.h>

#include <cstring>
#include <thread>

#include "core/base/sanitizers.hpp"
#include "hal/rt/rt_setup.hpp"

namespace rescue::hal {
namespace {

TEST(ThreadSanitizerBuild, RefusesSchedFifoWithItsReasonAndLeavesTheThreadAtNormalPriority) {
  // A scratch thread: a priority applied in another build ends with it.
  std::thread scratch([] {
    const Status set = set_fifo_priority(80);
    if (kThreadSanitizer) {
      ASSERT_FALSE(set.ok());
      EXPECT_EQ(set.error().code, Errc::unsupported);
      EXPECT_NE(std::strstr(set.error().what, "ThreadSanitizer build"), nullptr) << set.error().what;
      EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
    } else if (!set.ok()) {
      EXPECT_EQ(set.error().code, Errc::permission_denied) << set.error().what;  // only for want of privileges
    } else {
      EXPECT_EQ(sched_getscheduler(0), SCHED_FIFO);
    }
  });
  scratch.join();
}

TEST(ThreadSanitizerBuild, APriorityOutsideTheOsRangeIsStillAnInvalidArgument) {
  EXPECT_EQ(set_fifo_priority(0).error().code, Errc::invalid_argument);
  EXPECT_EQ(set_fifo_priority(100).error().code, Errc::invalid_argument);
}

}  // namespace
}  // namespace rescue::hal
