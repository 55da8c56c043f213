// The redundant link's cycle is heap-free: with the heap guard in strict mode (any allocation
// aborts), a thousand exchanges go out on both NICs of a two-port fake segment and come back
// merged, while a cable is cut and restored (closed, open at every place, two cuts).
#include <gtest/gtest.h>

#include "core/memory/heap_guard.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/link/datagram_link.hpp"
#include "tests/support/two_port_segment.hpp"

namespace rescue::ecat {
namespace {

TEST(RedundantLinkHeapFree, ThousandMergedExchangesAllocateNothing) {
  static test::TwoPortSegment segment{6};
  static DatagramLink link{segment.main()};
  link.set_ring(&segment.ring());
  std::array<std::uint8_t, 12> outputs{};
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);

  std::uint64_t full = 0;
  for (unsigned cycle = 0; cycle < 1000; ++cycle) {
    segment.restore_all();
    if (cycle % 3 == 1) segment.cut(cycle % 7);
    if (cycle % 3 == 2) {
      segment.cut(1);
      segment.cut(4);
    }
    FrameBuilder& frame = link.begin();
    (void)frame.add(Command::FRMW, link.index(), make_address(test::TwoPortSegment::kStation0, 0x0910), 8);
    (void)frame.add(Command::LRW, link.index(), 0, 12, ConstByteSpan(outputs));
    (void)frame.add(Command::BRD, link.index(), make_address(0, reg::kDlStatus), 2);
    const Result<FrameView> back = link.exchange(segment.clock().now() + 100 * hal::kNsPerUs);
    if (back.ok()) {
      auto d = back.value().begin();
      ++d;
      if ((*d).wkc() == 18) ++full;
    }
  }

  const HeapGuardCounters heap = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(heap.allocations, 0U);
  EXPECT_EQ(full, 667U) << "closed and single cuts: every slave counted; two cuts: not";
}

}  // namespace
}  // namespace rescue::ecat
