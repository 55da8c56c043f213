// Cable redundancy in the datagram link: a frame goes out on both NICs and the two copies that come
// back are merged (redundant_merge.hpp). Against a two-port fake segment of 6 slaves, for the ring
// closed and for a cut at every cable, every slave's working counter is counted exactly once and
// every slave's data is in the merged frame; the copies come back on the NIC the ring's shape says;
// position-addressed datagrams and FRMW never reach a slave through the ring port; a ring-side time
// write (a NOP at a station's 0x0910) reaches its slave through the ring port only, and an island
// time read (a NOP at a station's 0x0918) is an FRMW in the ring copy only. Two cuts leave
// exactly the slaves between them unanswered. Virtual time.
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/link/datagram_link.hpp"
#include "ecat/link/redundant_merge.hpp"
#include "tests/support/two_port_segment.hpp"

namespace rescue::ecat {
namespace {

using test::TwoPortSegment;
constexpr std::size_t kSlaves = 6;
constexpr std::size_t kClosed = ~std::size_t{0};

// What the exchange of one frame (LRW over every slave, BRD 0x0110, an FPRD per slave, APRD of
// position 0, FRMW of slave 0's clock) gave back.
struct Exchanged {
  std::uint16_t lrw_wkc{0};
  std::array<std::uint8_t, 2 * kSlaves> image{};
  std::uint16_t brd_wkc{0};
  std::array<std::uint16_t, kSlaves> fprd_wkc{};
  std::array<std::uint8_t, kSlaves> fprd_data{};
  std::uint16_t aprd_wkc{0};
  std::uint16_t frmw_wkc{0};
  CopyReturns returns{};
};

class RedundantLink : public ::testing::Test {
 protected:
  RedundantLink() { link.set_ring(&segment.ring()); }

  Exchanged exchange() {
    Exchanged e;
    FrameBuilder& frame = link.begin();
    std::array<std::uint8_t, 2 * kSlaves> outputs{};
    for (std::size_t i = 0; i < kSlaves; ++i) outputs[i] = static_cast<std::uint8_t>(0x10 + i);
    EXPECT_TRUE(frame.add(Command::LRW, link.index(), 0, 2 * kSlaves, ConstByteSpan(outputs)).ok());
    EXPECT_TRUE(frame.add(Command::BRD, link.index(), make_address(0, reg::kDlStatus), 2).ok());
    for (std::size_t i = 0; i < kSlaves; ++i) {
      const auto station = static_cast<std::uint16_t>(TwoPortSegment::kStation0 + i);
      EXPECT_TRUE(frame.add(Command::FPRD, link.index(), make_address(station, reg::kDlStatus), 2).ok());
    }
    EXPECT_TRUE(frame.add(Command::APRD, link.index(), make_address(0, 0), 2).ok());
    EXPECT_TRUE(frame.add(Command::FRMW, link.index(), make_address(TwoPortSegment::kStation0, 0x0910), 8).ok());
    const Result<FrameView> back = link.exchange(segment.clock().now() + 100 * hal::kNsPerUs);
    EXPECT_TRUE(back.ok());
    if (!back.ok()) return e;
    e.returns = link.copy_returns();
    auto d = back.value().begin();
    e.lrw_wkc = (*d).wkc();
    std::memcpy(e.image.data(), (*d).data().data(), e.image.size());
    ++d;
    e.brd_wkc = (*d).wkc();
    ++d;
    for (std::size_t i = 0; i < kSlaves; ++i, ++d) {
      e.fprd_wkc[i] = (*d).wkc();
      e.fprd_data[i] = (*d).data()[0];
    }
    e.aprd_wkc = (*d).wkc();
    ++d;
    e.frmw_wkc = (*d).wkc();
    EXPECT_EQ((*d).command(), Command::FRMW) << "the merged frame carries the commands sent";
    return e;
  }

  TwoPortSegment segment{kSlaves};
  DatagramLink link{segment.main()};
};

TEST_F(RedundantLink, EveryBreakPositionGivesFullCountersAndEverySlavesData) {
  for (std::size_t cut = 0; cut <= kSlaves + 1; ++cut) {
    const std::size_t cable = cut == kSlaves + 1 ? kClosed : cut;
    SCOPED_TRACE(cable == kClosed ? std::string("closed") : "cable " + std::to_string(cable));
    segment.restore_all();
    if (cable != kClosed) segment.cut(cable);
    const Exchanged e = exchange();
    EXPECT_EQ(e.lrw_wkc, 3 * kSlaves);
    EXPECT_EQ(e.brd_wkc, kSlaves);
    for (std::size_t i = 0; i < kSlaves; ++i) {
      EXPECT_EQ(e.image[kSlaves + i], TwoPortSegment::input_byte(i)) << "slave " << i;
      EXPECT_EQ(e.image[i], 0x10 + i) << "outputs come back as sent";
      EXPECT_EQ(segment.output_of(i), 0x10 + i);
      EXPECT_EQ(e.fprd_wkc[i], 1U) << "slave " << i;
      EXPECT_EQ(e.fprd_data[i], TwoPortSegment::fprd_byte(i));
    }
    // Position 0 and the reference clock's FRMW go by the main port only.
    EXPECT_EQ(e.aprd_wkc, cable == 0 ? 0U : 1U);
    const std::size_t main_reach = cable == kClosed ? kSlaves : cable;
    EXPECT_EQ(e.frmw_wkc, main_reach);
    // Where the copies came back.
    EXPECT_EQ(e.returns.main_back, cable != 0);
    EXPECT_EQ(e.returns.ring_back, cable != kSlaves);
    if (cable == kClosed) {
      EXPECT_EQ(e.returns.main_on, Port::ring);
      EXPECT_EQ(e.returns.ring_on, Port::main);
    } else {
      EXPECT_TRUE(!e.returns.main_back || e.returns.main_on == Port::main);
      EXPECT_TRUE(!e.returns.ring_back || e.returns.ring_on == Port::ring);
    }
    // The BRD's counter in each copy says how far each side reaches.
    EXPECT_EQ(e.returns.counters.main[1], main_reach);
    EXPECT_EQ(e.returns.counters.ring[1], kSlaves - main_reach);
  }
  for (std::size_t i = 0; i < kSlaves; ++i) EXPECT_EQ(segment.position_hits(i), i == 0 ? kSlaves + 1 : 0U);
  EXPECT_EQ(link.stats().malformed, 0U);
  EXPECT_EQ(link.stats().timeouts, 0U);
}

// DC across a break (ecat/master/ring_dc_service.hpp): the time write to a slave behind the break is
// a NOP in the main copy and an FPWR of 0x0910 in the ring copy, so only a slave the ring copy
// processes takes it; with the ring closed nobody does.
TEST_F(RedundantLink, RingSideTimeWritesReachOnlyTheSlavesBehindTheBreak) {
  for (std::size_t cut = 0; cut <= kSlaves + 1; ++cut) {
    const std::size_t cable = cut == kSlaves + 1 ? kClosed : cut;
    SCOPED_TRACE(cable == kClosed ? std::string("closed") : "cable " + std::to_string(cable));
    segment.restore_all();
    if (cable != kClosed) segment.cut(cable);
    FrameBuilder& frame = link.begin();
    const std::array<std::uint8_t, 8> time{1, 2, 3, 4, 5, 6, 7, 8};
    for (std::size_t i = 0; i < kSlaves; ++i) {
      const auto station = static_cast<std::uint16_t>(TwoPortSegment::kStation0 + i);
      ASSERT_TRUE(frame.add(Command::NOP, link.index(), ring_side_time_write_address(station), 8, ConstByteSpan(time)).ok());
    }
    const Result<FrameView> back = link.exchange(segment.clock().now() + 100 * hal::kNsPerUs);
    ASSERT_TRUE(back.ok());
    std::size_t i = 0;
    for (const DatagramView d : back.value()) {
      const bool behind = cable != kClosed && i >= cable;
      EXPECT_EQ(d.wkc(), behind ? 1U : 0U) << "slave " << i;
      EXPECT_EQ(d.command(), Command::NOP) << "the merged frame carries the commands sent";
      EXPECT_EQ(link.copy_returns().counters.main[i], 0U) << "slave " << i << ": a NOP in the main copy";
      ++i;
    }
  }
  EXPECT_EQ(link.stats().malformed, 0U);
}

// DC across a break, the island (ecat/master/ring_dc_service.hpp): the island time read is a NOP in
// the main copy and an FRMW of 0x0910 in the ring copy, so the slaves the ring copy processes take
// it (all of them: an FRMW is written by every slave it passes) and nobody with the ring closed.
TEST_F(RedundantLink, IslandTimeReadsAreAnFrmwInTheRingCopyOnly) {
  for (std::size_t cut = 0; cut <= kSlaves + 1; ++cut) {
    const std::size_t cable = cut == kSlaves + 1 ? kClosed : cut;
    SCOPED_TRACE(cable == kClosed ? std::string("closed") : "cable " + std::to_string(cable));
    segment.restore_all();
    if (cable != kClosed) segment.cut(cable);
    std::array<unsigned, kSlaves> hits_before{};
    for (std::size_t i = 0; i < kSlaves; ++i) hits_before[i] = segment.frmw_hits(i);
    FrameBuilder& frame = link.begin();
    const std::size_t first = cable == kClosed || cable >= kSlaves ? 0 : cable;
    const auto station = static_cast<std::uint16_t>(TwoPortSegment::kStation0 + first);
    ASSERT_TRUE(frame.add(Command::NOP, link.index(), island_time_read_address(station), 8).ok());
    const Result<FrameView> back = link.exchange(segment.clock().now() + 100 * hal::kNsPerUs);
    ASSERT_TRUE(back.ok());
    const std::size_t behind = cable == kClosed ? 0 : kSlaves - cable;
    const DatagramView d = *back.value().begin();
    EXPECT_EQ(d.wkc(), behind);
    EXPECT_EQ(d.command(), Command::NOP) << "the merged frame carries the commands sent";
    EXPECT_EQ(link.copy_returns().counters.main[0], 0U) << "a NOP in the main copy";
    for (std::size_t i = 0; i < kSlaves; ++i) {
      const bool is_behind = cable != kClosed && i >= cable;
      EXPECT_EQ(segment.frmw_hits(i) - hits_before[i], is_behind ? 1U : 0U) << "slave " << i;
    }
  }
  EXPECT_EQ(link.stats().malformed, 0U);
}

TEST_F(RedundantLink, TwoCutsLeaveExactlyTheSlavesBetweenThemUnanswered) {
  for (std::size_t a = 0; a <= kSlaves; ++a) {
    for (std::size_t b = a + 1; b <= kSlaves; ++b) {
      if (a == 0 && b == kSlaves) continue;  // both master ports cut: nothing back (the test below)
      SCOPED_TRACE("cables " + std::to_string(a) + " and " + std::to_string(b));
      segment.restore_all();
      segment.cut(a);
      segment.cut(b);
      const Exchanged e = exchange();
      const std::size_t lost = b - a;  // slaves a .. b-1
      EXPECT_EQ(e.lrw_wkc, 3 * (kSlaves - lost));
      EXPECT_EQ(e.brd_wkc, kSlaves - lost);
      for (std::size_t i = 0; i < kSlaves; ++i) {
        const bool between = i >= a && i < b;
        EXPECT_EQ(e.fprd_wkc[i], between ? 0U : 1U) << "slave " << i;
        EXPECT_EQ(e.image[kSlaves + i], between ? 0 : TwoPortSegment::input_byte(i)) << "slave " << i;
      }
    }
  }
}

TEST_F(RedundantLink, NothingBackOnEitherNicIsATimeout) {
  segment.cut(0);
  segment.cut(kSlaves);
  FrameBuilder& frame = link.begin();
  ASSERT_TRUE(frame.add(Command::BRD, link.index(), 0, 2).ok());
  const Result<FrameView> back = link.exchange(segment.clock().now() + 100 * hal::kNsPerUs);
  ASSERT_FALSE(back.ok());
  EXPECT_EQ(back.error().code, Errc::timeout);
  EXPECT_EQ(link.stats().timeouts, 1U);
}

TEST_F(RedundantLink, ACutAtAMasterPortDoesNotHoldEveryExchangeToItsDeadline) {
  constexpr hal::Nanoseconds kWindow = 100 * hal::kNsPerUs;
  for (const std::size_t port_cable : {std::size_t{0}, kSlaves}) {
    SCOPED_TRACE("cable " + std::to_string(port_cable));
    segment.restore_all();
    (void)exchange();
    segment.cut(port_cable);
    hal::Nanoseconds sent = segment.clock().now();
    (void)exchange();  // the copy sent by the cut port is waited for until the deadline, once
    EXPECT_EQ(segment.clock().now() - sent, kWindow);
    sent = segment.clock().now();
    const Exchanged e = exchange();
    EXPECT_EQ(segment.clock().now() - sent, TwoPortSegment::kRoundTrip) << "then no longer";
    EXPECT_EQ(e.lrw_wkc, 3 * kSlaves);
    segment.restore(port_cable);
    for (int i = 0; i < 3; ++i) (void)exchange();
    EXPECT_TRUE(link.copy_returns().main_back && link.copy_returns().ring_back) << "repaired: both copies again";
    EXPECT_EQ(link.copy_returns().main_on, Port::ring);
  }
}

TEST_F(RedundantLink, TransfersAndStreamsAreMergedToo) {
  segment.cut(3);
  std::array<std::uint8_t, 2> data{};
  const Result<std::uint16_t> wkc = link.transfer(Command::BRD, 0, ByteSpan(data), 100 * hal::kNsPerUs);
  ASSERT_TRUE(wkc.ok());
  EXPECT_EQ(wkc.value(), kSlaves);
  std::array<std::uint8_t, 2> fprd{};
  const Result<std::uint16_t> far = link.transfer(Command::FPRD, make_address(TwoPortSegment::kStation0 + 5, 0), ByteSpan(fprd),
                                                  100 * hal::kNsPerUs);
  ASSERT_TRUE(far.ok());
  EXPECT_EQ(far.value(), 1U) << "a slave behind the cut answers through the ring port";
  EXPECT_EQ(fprd[0], TwoPortSegment::fprd_byte(5));
  std::array<std::uint8_t, 2> streamed{};
  const Result<StreamOutcome> s = link.stream(Command::BRD, 0, ByteSpan(streamed), 5, 4, 100 * hal::kNsPerUs);
  ASSERT_TRUE(s.ok());
  EXPECT_EQ(s.value().returned, 5U);
  EXPECT_EQ(s.value().last_wkc, kSlaves);
}

}  // namespace
}  // namespace rescue::ecat
