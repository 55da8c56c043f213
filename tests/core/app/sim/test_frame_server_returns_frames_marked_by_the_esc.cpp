// The serve loop behind `rescue-motion sim`: every frame received goes through the processor and
// back out of the same NIC with SOURCE_MAC[1] set, as a real ESC returns it; frames the processor
// keeps are counted and not sent; a quiet NIC is a timeout, not a failure. Runs on a fake NIC on
// virtual time (the real raw socket is covered by the netns tests).
#include <cstdint>
#include <cstring>
#include <deque>
#include <vector>

#include <gtest/gtest.h>

#include "core/app/sim/frame_server.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/test_frames.hpp"

namespace rescue::app {
namespace {

using Frame = std::vector<std::uint8_t>;

class FakeNic final : public hal::Nic {
 public:
  Status send(ConstByteSpan frame) noexcept override {
    if (fail_sends) {
      ++stats_.send_errors;
      return make_error(Errc::busy, "fake send failure");
    }
    sent.emplace_back(frame.begin(), frame.end());
    ++stats_.frames_sent;
    return Status::success();
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    if (inbox.empty()) {
      clock_.sleep_until(deadline);
      ++stats_.receive_timeouts;
      return make_error(Errc::timeout, "fake quiet");
    }
    const Frame frame = inbox.front();
    inbox.pop_front();
    std::memcpy(buffer.data(), frame.data(), frame.size());
    ++stats_.frames_received;
    return frame.size();
  }
  hal::Clock& clock() noexcept override { return clock_; }
  const char* name() const noexcept override { return "fake"; }
  hal::NicStats stats() const noexcept override { return stats_; }

  std::deque<Frame> inbox;
  std::vector<Frame> sent;
  bool fail_sends{false};

 private:
  hal::VirtualClock clock_{1000};
  hal::NicStats stats_{};
};

// A segment of `slaves` slaves that all answer every datagram; keeps frames it cannot parse.
class EchoSegment final : public FrameProcessor {
 public:
  explicit EchoSegment(std::uint16_t slaves) : slaves_(slaves) {}
  std::size_t slave_count() const noexcept override { return slaves_; }
  Result<std::size_t> process(ByteSpan frame, hal::Nanoseconds arrival) noexcept override {
    last_arrival = arrival;
    auto view = ecat::MutableFrameView::parse(frame);
    if (!view.ok()) return view.error();
    for (auto datagram : view.value()) datagram.set_wkc(static_cast<std::uint16_t>(datagram.wkc() + slaves_));
    return frame.size();
  }
  void idle(hal::Nanoseconds now) noexcept override { idle_calls.push_back(now); }
  hal::Nanoseconds last_arrival{-1};
  std::vector<hal::Nanoseconds> idle_calls;

 private:
  std::uint16_t slaves_;
};

constexpr ecat::MacAddress kMasterMac{0x00, 0x1B, 0x21, 0x0A, 0x0B, 0x0C};

TEST(FrameServer, ReturnsTheProcessedFrameWithTheSourceMarkedAsByAnEsc) {
  FakeNic nic;
  EchoSegment segment(23);
  FrameServer server(nic, segment);
  nic.inbox.push_back(rescue::testing::make_brd_frame(kMasterMac, 5));

  ASSERT_TRUE(server.serve_one(nic.clock().now() + hal::kNsPerMs).ok());
  ASSERT_EQ(nic.sent.size(), 1U);
  auto view = ecat::FrameView::parse(ConstByteSpan(nic.sent[0].data(), nic.sent[0].size()));
  ASSERT_TRUE(view.ok());
  EXPECT_EQ((*view.value().begin()).wkc(), 23);
  EXPECT_EQ((*view.value().begin()).index(), 5);
  ecat::MacAddress expected_source = kMasterMac;
  expected_source[0] |= 0x02;
  EXPECT_EQ(view.value().header().source, expected_source);
  EXPECT_EQ(view.value().header().destination, ecat::kBroadcastMac);
  EXPECT_EQ(segment.last_arrival, nic.clock().now());
  EXPECT_EQ(server.counters().frames_received, 1U);
  EXPECT_EQ(server.counters().frames_returned, 1U);
}

TEST(FrameServer, MarkingIsIdempotentLikeAChainOfEscs) {
  Frame frame = rescue::testing::make_brd_frame(ecat::MacAddress{0x02, 1, 1, 1, 1, 1}, 0);
  mark_processed_by_esc(ByteSpan(frame.data(), frame.size()));
  mark_processed_by_esc(ByteSpan(frame.data(), frame.size()));
  EXPECT_EQ(frame[6], 0x02);
  for (int i = 7; i < 12; ++i) EXPECT_EQ(frame[static_cast<std::size_t>(i)], 1);
  Frame runt(10, 0);
  mark_processed_by_esc(ByteSpan(runt.data(), runt.size()));  // too short: left alone
  EXPECT_EQ(runt, Frame(10, 0));
}

TEST(FrameServer, FramesTheSegmentKeepsAreCountedNotSent) {
  FakeNic nic;
  EchoSegment segment(2);
  FrameServer server(nic, segment);
  Frame broken = rescue::testing::make_brd_frame(kMasterMac, 1);
  broken[14] = 0xFF;  // EtherCAT length larger than the frame
  nic.inbox.push_back(broken);
  ASSERT_TRUE(server.serve_one(nic.clock().now() + hal::kNsPerMs).ok());
  EXPECT_TRUE(nic.sent.empty());
  EXPECT_EQ(server.counters().frames_not_returned, 1U);
}

TEST(FrameServer, SendFailureIsCountedAndServingGoesOn) {
  FakeNic nic;
  EchoSegment segment(1);
  FrameServer server(nic, segment);
  nic.fail_sends = true;
  nic.inbox.push_back(rescue::testing::make_brd_frame(kMasterMac, 1));
  ASSERT_TRUE(server.serve_one(nic.clock().now() + hal::kNsPerMs).ok());
  EXPECT_EQ(server.counters().send_errors, 1U);
  nic.fail_sends = false;
  nic.inbox.push_back(rescue::testing::make_brd_frame(kMasterMac, 2));
  ASSERT_TRUE(server.serve_one(nic.clock().now() + hal::kNsPerMs).ok());
  EXPECT_EQ(server.counters().frames_returned, 1U);
}

TEST(FrameServer, QuietNicIsATimeoutAtTheDeadline) {
  FakeNic nic;
  EchoSegment segment(1);
  FrameServer server(nic, segment);
  const hal::Nanoseconds deadline = nic.clock().now() + 100 * hal::kNsPerMs;
  const Status status = server.serve_one(deadline);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().code, Errc::timeout);
  EXPECT_EQ(nic.clock().now(), deadline);
  EXPECT_EQ(server.counters().frames_received, 0U);
}

// Issue 11 item 4: the slaves' time runs while the wire is quiet, so the first frame after a long
// idle spell is not held back by the simulation of the whole spell.
TEST(FrameServer, AQuietWaitLetsTheSegmentCatchUpWithTheTime) {
  FakeNic nic;
  EchoSegment segment(1);
  FrameServer server(nic, segment);
  hal::Nanoseconds deadline = 0;
  for (int i = 0; i < 3; ++i) {
    deadline = nic.clock().now() + 2 * hal::kNsPerMs;
    EXPECT_EQ(server.serve_one(deadline).error().code, Errc::timeout);
  }
  ASSERT_EQ(segment.idle_calls.size(), 3U);
  EXPECT_EQ(segment.idle_calls.back(), deadline) << "caught up with the end of the wait";
  EXPECT_EQ(server.counters().idle_steps, 3U);
  nic.inbox.push_back(rescue::testing::make_brd_frame(kMasterMac, 1));
  ASSERT_TRUE(server.serve_one(nic.clock().now() + 2 * hal::kNsPerMs).ok());
  EXPECT_EQ(segment.idle_calls.size(), 3U) << "a frame is served, not an idle step";
}

}  // namespace
}  // namespace rescue::app
