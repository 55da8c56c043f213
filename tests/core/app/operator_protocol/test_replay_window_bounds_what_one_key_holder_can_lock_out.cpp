// What one key holder can do to the replay window (docs/protocol.md "Senders", docs/security.md):
// a sequence more than kMaxSequenceLeadNs ahead of the robot's clock is refused (out_of_range), so
// one datagram with sequence 2^64-1 no longer locks its sender out for the epoch; and other senders
// can fill the table only up to kOperatorSender's kept slot.
#include <gtest/gtest.h>

#include <cstdint>

#include "core/app/operator_protocol/replay_window.hpp"

namespace rescue::app::protocol {
namespace {

constexpr std::uint64_t kT0 = 1'700'000'000'000'000'000ULL;  // the robot's clock

TEST(ReplayWindowLockout, ASequenceFarAheadOfTheRobotsClockIsRefusedAndMovesNoWindow) {
  ReplayWindow w;
  w.begin_epoch(3);
  const Status max = w.accept(kOperatorSender, UINT64_MAX, kT0);
  ASSERT_FALSE(max.ok());
  EXPECT_EQ(max.error().code, Errc::out_of_range);
  EXPECT_EQ(w.senders(), 0U) << "refused before it takes a slot";
  EXPECT_EQ(w.accept(kOperatorSender, kT0 + kMaxSequenceLeadNs + 1, kT0).error().code, Errc::out_of_range);
  // The operator's own request, numbered by its clock, is served.
  EXPECT_TRUE(w.accept(kOperatorSender, kT0 - 5, kT0).ok());
  // The furthest a key holder can push it: the lead; the operator is served again once the robot's
  // clock has moved on by that much.
  EXPECT_TRUE(w.accept(kOperatorSender, kT0 + kMaxSequenceLeadNs, kT0).ok());
  EXPECT_EQ(w.accept(kOperatorSender, kT0 + 1, kT0 + 1).error().code, Errc::refused);
  const std::uint64_t later = kT0 + kMaxSequenceLeadNs + 1;
  EXPECT_TRUE(w.accept(kOperatorSender, later, later).ok());
}

TEST(ReplayWindowLockout, OtherSendersLeaveTheOperatorsSlotFree) {
  ReplayWindow w;
  w.begin_epoch(4);
  for (std::uint32_t s = 2; s < 2 + kMaxSenders - 1; ++s) ASSERT_TRUE(w.accept(s, kT0, kT0).ok()) << s;
  const Status full = w.accept(2 + kMaxSenders - 1, kT0, kT0);
  ASSERT_FALSE(full.ok());
  EXPECT_EQ(full.error().code, Errc::capacity_exceeded);
  EXPECT_TRUE(w.accept(kOperatorSender, kT0, kT0).ok()) << "the kept slot";
  EXPECT_EQ(w.senders(), kMaxSenders);
}

}  // namespace
}  // namespace rescue::app::protocol
