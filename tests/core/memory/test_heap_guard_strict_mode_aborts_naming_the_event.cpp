// Strict mode: the first allocation after init complete aborts the process with a line naming the
// allocation. Death tests run the statement in a forked child and match its stderr.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>

#include "core/memory/heap_guard.hpp"
#include "tests/support/do_not_optimize.hpp"

namespace rescue {
namespace {

using test::do_not_optimize;

struct alignas(64) CacheLine {
  unsigned char bytes[64];
};

void allocate_48_bytes_after_init() {
  declare_init_complete(HeapGuardMode::strict);
  do_not_optimize(::operator new(48));
}

TEST(HeapGuardDeathTest, OperatorNewAfterInitAbortsWithItsSize) {
  reopen_init_for_testing();
  EXPECT_EXIT(allocate_48_bytes_after_init(), testing::KilledBySignal(SIGABRT),
              "heap guard: operator new\\(48\\) after init complete");
}

TEST(HeapGuardDeathTest, AlignedArrayNewNamesItsAlignment) {
  reopen_init_for_testing();
  EXPECT_EXIT(
      {
        declare_init_complete(HeapGuardMode::strict);
        do_not_optimize(new CacheLine[2]);
      },
      testing::KilledBySignal(SIGABRT), "heap guard: aligned operator new\\[\\]\\(128, align 64\\) after init complete");
}

TEST(HeapGuardDeathTest, MallocAfterInitAborts) {
  if (!heap_guard_covers_malloc()) GTEST_SKIP() << "sanitizer build: the sanitizer owns malloc, only operator new is guarded";
  reopen_init_for_testing();
  EXPECT_EXIT(
      {
        declare_init_complete(HeapGuardMode::strict);
        do_not_optimize(std::malloc(100));
      },
      testing::KilledBySignal(SIGABRT), "heap guard: malloc\\(100\\) after init complete");
}

TEST(HeapGuardDeathTest, SwitchingToStrictLaterAbortsOnTheNextAllocation) {
  reopen_init_for_testing();
  EXPECT_EXIT(
      {
        declare_init_complete(HeapGuardMode::count);
        do_not_optimize(::operator new(8));  // counted, tolerated
        set_heap_guard_mode(HeapGuardMode::strict);
        do_not_optimize(::operator new(16));
      },
      testing::KilledBySignal(SIGABRT), "operator new\\(16\\)");
}

}  // namespace
}  // namespace rescue
