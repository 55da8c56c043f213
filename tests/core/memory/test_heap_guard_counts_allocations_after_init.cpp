// The heap guard counts every allocation made after declare_init_complete(), by kind, and none
// before. Each test reads the counters first and re-opens the init phase before asserting, so
// GoogleTest's own allocations are never counted.
#include <gtest/gtest.h>

#include <malloc.h>

#include <cstdlib>
#include <cstring>
#include <memory>

#include "core/memory/heap_guard.hpp"
#include "tests/support/do_not_optimize.hpp"

namespace rescue {
namespace {

using test::do_not_optimize;

std::uint64_t of(const HeapGuardCounters& counters, HeapEvent event) {
  return counters.by_kind[static_cast<std::size_t>(event)];
}

struct alignas(64) CacheLine {
  unsigned char bytes[64];
};

TEST(HeapGuard, NothingIsCountedBeforeInitComplete) {
  reopen_init_for_testing();
  auto* p = new int(3);
  do_not_optimize(p);
  delete p;
  const HeapGuardCounters counters = heap_guard_counters();
  EXPECT_FALSE(heap_init_complete());
  EXPECT_EQ(counters.allocations, 0u);
  EXPECT_EQ(counters.frees, 0u);
}

TEST(HeapGuard, CountsEveryOperatorNewForm) {
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::count);
  void* raw = ::operator new(48);
  do_not_optimize(raw);
  ::operator delete(raw);
  auto* array = new int[4];
  do_not_optimize(array);
  delete[] array;
  auto* line = new CacheLine;  // over-aligned: the align_val_t form
  do_not_optimize(line);
  delete line;
  auto* lines = new CacheLine[2];
  do_not_optimize(lines);
  delete[] lines;
  auto* nothrow = new (std::nothrow) int(1);
  do_not_optimize(nothrow);
  delete nothrow;
  auto owned = std::make_unique<long>(5);  // library code allocating on our behalf
  do_not_optimize(owned.get());
  owned.reset();
  const HeapGuardCounters counters = heap_guard_counters();
  reopen_init_for_testing();

  EXPECT_EQ(of(counters, HeapEvent::operator_new), 3u);  // 48 bytes, nothrow int, make_unique
  EXPECT_EQ(of(counters, HeapEvent::operator_new_array), 1u);
  EXPECT_EQ(of(counters, HeapEvent::operator_new_aligned), 1u);
  EXPECT_EQ(of(counters, HeapEvent::operator_new_array_aligned), 1u);
  EXPECT_EQ(counters.allocations, 6u);
  EXPECT_EQ(counters.bytes, 48u + 4 * sizeof(int) + 64 + 128 + sizeof(int) + sizeof(long));
  EXPECT_EQ(counters.frees, 6u);
}

TEST(HeapGuard, CountsEveryCAllocatorEntry) {
  if (!heap_guard_covers_malloc()) GTEST_SKIP() << "sanitizer build: the sanitizer owns malloc, only operator new is guarded";
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::count);
  void* m = std::malloc(100);
  do_not_optimize(m);
  void* r = std::realloc(m, 200);
  do_not_optimize(r);
  std::free(r);
  void* c = std::calloc(3, 10);
  do_not_optimize(c);
  std::free(c);
  void* a = std::aligned_alloc(64, 128);
  do_not_optimize(a);
  std::free(a);
  void* pm = nullptr;
  const int pm_status = posix_memalign(&pm, 64, 32);
  do_not_optimize(pm);
  std::free(pm);
  void* ma = memalign(32, 16);
  do_not_optimize(ma);
  std::free(ma);
  char* copy = strdup("glibc allocates through malloc too");
  do_not_optimize(copy);
  std::free(copy);
  const HeapGuardCounters counters = heap_guard_counters();
  reopen_init_for_testing();

  EXPECT_EQ(pm_status, 0);
  EXPECT_EQ(of(counters, HeapEvent::malloc), 2u);  // malloc + strdup
  EXPECT_EQ(of(counters, HeapEvent::realloc), 1u);
  EXPECT_EQ(of(counters, HeapEvent::calloc), 1u);
  EXPECT_EQ(of(counters, HeapEvent::aligned_alloc), 1u);
  EXPECT_EQ(of(counters, HeapEvent::posix_memalign), 1u);
  EXPECT_EQ(of(counters, HeapEvent::memalign), 1u);
  EXPECT_EQ(counters.allocations, 7u);
  EXPECT_EQ(counters.frees, 6u);  // realloc moved or kept m: one free for the pair
}

TEST(HeapGuard, AllowedScopeCountsSeparatelyAndNeverAborts) {
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);
  {
    const HeapAllowedScope allowed;
    auto* p = new int(1);
    do_not_optimize(p);
    delete p;
  }
  const HeapGuardCounters counters = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(counters.allocations, 0u);
  EXPECT_EQ(counters.allowed, 1u);
}

TEST(HeapGuard, EveryEventHasAName) {
  for (std::size_t i = 0; i < kHeapEventKinds; ++i) {
    EXPECT_STRNE(to_string(static_cast<HeapEvent>(i)), "unknown allocation") << i;
  }
}

}  // namespace
}  // namespace rescue
