// Cable redundancy: a copy damaged on a cable is lost at the master, but the slaves it passed
// carried out its datagrams (docs/redundancy.md "A copy lost in flight"). Against a two-port fake
// segment of 6 slaves: the link marks such an exchange (CopyReturns::copy_lost) when the lost copy
// may have passed slaves (the main copy of the closed ring, either copy of an open ring), not when
// it passed none (the ring copy of the closed ring, a copy that did not come back last time either:
// a master port's cut). answer_lost_with_a_copy names exactly the datagrams no returned copy
// counted. Virtual time.
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/link/datagram_link.hpp"
#include "ecat/link/redundant_merge.hpp"
#include "tests/support/two_port_segment.hpp"

namespace rescue::ecat {
namespace {

using test::TwoPortSegment;
constexpr std::size_t kSlaves = 6;

// One frame: an FPRD per slave. Per slave: whether its answer counts as lost with a copy.
struct Exchanged {
  bool back{false};
  bool copy_lost{false};
  std::array<bool, kSlaves> lost{};
  std::array<std::uint16_t, kSlaves> wkc{};
};

class RedundantLinkLostCopy : public ::testing::Test {
 protected:
  RedundantLinkLostCopy() { link.set_ring(&segment.ring()); }

  Exchanged exchange() {
    Exchanged e;
    FrameBuilder& frame = link.begin();
    for (std::size_t i = 0; i < kSlaves; ++i) {
      const auto station = static_cast<std::uint16_t>(TwoPortSegment::kStation0 + i);
      EXPECT_TRUE(frame.add(Command::FPRD, link.index(), make_address(station, reg::kDlStatus), 2).ok());
    }
    const Result<FrameView> back = link.exchange(segment.clock().now() + 100 * hal::kNsPerUs);
    e.back = back.ok();
    if (!back.ok()) return e;
    e.copy_lost = link.copy_returns().copy_lost;
    std::size_t i = 0;
    for (const DatagramView d : back.value()) {
      e.wkc[i] = d.wkc();
      e.lost[i] = answer_lost_with_a_copy(link.copy_returns(), d);
      ++i;
    }
    return e;
  }

  TwoPortSegment segment{kSlaves};
  DatagramLink link{segment.main()};
};

TEST_F(RedundantLinkLostCopy, TheMainCopyOfTheClosedRingTakesEveryAnswer) {
  ASSERT_FALSE(exchange().copy_lost);
  segment.damage_next(false);
  const Exchanged e = exchange();
  ASSERT_TRUE(e.back) << "the ring copy comes back round the ring";
  EXPECT_TRUE(e.copy_lost);
  for (std::size_t i = 0; i < kSlaves; ++i) {
    EXPECT_EQ(e.wkc[i], 0u) << i;
    EXPECT_TRUE(e.lost[i]) << i;
  }
  EXPECT_FALSE(exchange().copy_lost) << "the next exchange is whole again";
}

TEST_F(RedundantLinkLostCopy, TheRingCopyOfTheClosedRingTakesNone) {
  ASSERT_FALSE(exchange().copy_lost);
  segment.damage_next(true);
  const Exchanged e = exchange();
  ASSERT_TRUE(e.back);
  EXPECT_FALSE(e.copy_lost);
  for (std::size_t i = 0; i < kSlaves; ++i) {
    EXPECT_EQ(e.wkc[i], 1u) << i;
    EXPECT_FALSE(e.lost[i]) << i;
  }
}

TEST_F(RedundantLinkLostCopy, OnAnOpenRingACopyTakesTheAnswersOfItsSideOnly) {
  constexpr std::size_t kCable = 2;  // slaves 0, 1 on the main side, 2 .. 5 on the ring side
  segment.cut(kCable);
  ASSERT_FALSE(exchange().copy_lost);
  for (const bool ring : {false, true}) {
    segment.damage_next(ring);
    const Exchanged e = exchange();
    ASSERT_TRUE(e.back) << ring;
    EXPECT_TRUE(e.copy_lost) << ring;
    for (std::size_t i = 0; i < kSlaves; ++i) {
      const bool on_damaged_side = ring ? i >= kCable : i < kCable;
      EXPECT_EQ(e.lost[i], on_damaged_side) << "ring " << ring << " slave " << i;
      EXPECT_EQ(e.wkc[i], on_damaged_side ? 0u : 1u) << "ring " << ring << " slave " << i;
    }
    ASSERT_FALSE(exchange().copy_lost) << ring;
  }
}

TEST_F(RedundantLinkLostCopy, AMasterPortsCutIsNoLostCopyOnceItIsKnown) {
  segment.cut(0);  // the main port's cable: the ring copy reaches every slave, the main copy none
  (void)exchange();  // the first exchange after the cut: the main copy was expected
  for (int k = 0; k < 3; ++k) {
    const Exchanged e = exchange();
    ASSERT_TRUE(e.back);
    EXPECT_FALSE(e.copy_lost) << k;
    for (std::size_t i = 0; i < kSlaves; ++i) EXPECT_FALSE(e.lost[i]) << k << " " << i;
  }
}

}  // namespace
}  // namespace rescue::ecat
