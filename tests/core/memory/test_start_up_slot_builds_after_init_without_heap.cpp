// StartUpSlot<T>: its memory is taken by reserve() at start-up, and the object built in it by
// emplace() after init complete allocates nothing (heap guard armed); emplace builds once, with the
// first call's arguments, aligned as T asks; the object is not in static storage.
#include <gtest/gtest.h>

#include <cstdint>

#include "core/memory/heap_guard.hpp"
#include "core/memory/start_up_slot.hpp"

namespace rescue {
namespace {

struct alignas(64) Large {
  explicit Large(int seed) noexcept : first(seed) {}
  int first;
  unsigned char bytes[1 << 20]{};  // a megabyte: what a static would add to every command's image
};

TEST(StartUpSlot, BuildsAfterInitWithoutTheHeapAndOnlyOnce) {
  reopen_init_for_testing();
  static StartUpSlot<Large> slot;
  EXPECT_FALSE(slot.reserved());
  ASSERT_TRUE(slot.reserve());
  ASSERT_TRUE(slot.reserve()) << "a second reserve keeps the memory it has";
  EXPECT_FALSE(slot.built());

  declare_init_complete(HeapGuardMode::count);
  Large& built = slot.emplace(7);
  Large& again = slot.emplace(8);
  const HeapGuardCounters counters = heap_guard_counters();
  reopen_init_for_testing();

  EXPECT_EQ(counters.allocations, 0U) << "emplace after init takes no heap";
  EXPECT_TRUE(slot.built());
  EXPECT_EQ(&built, &again);
  EXPECT_EQ(built.first, 7) << "built once, with the first call's arguments";
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(&built) % alignof(Large), 0U);
  EXPECT_LT(sizeof slot, std::size_t{64}) << "the slot itself is two pointers, not the object";
}

}  // namespace
}  // namespace rescue
