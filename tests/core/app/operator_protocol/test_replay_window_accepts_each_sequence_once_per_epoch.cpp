// The replay window (docs/protocol.md "Replay protection"): within an epoch a sequence is accepted
// once, one older than the window never; a new epoch forgets every window and empties the sender
// table (whatever was accepted before is refused by the socket handler's epoch check, see
// test_socket_handler_refuses_other_epochs_other_robots_and_a_full_sender_table); a 17th sender is
// refused as such, never taken for a replay.
#include <gtest/gtest.h>

#include "core/app/operator_protocol/replay_window.hpp"

namespace rescue::app::protocol {
namespace {

constexpr std::uint64_t kT0 = 1'700'000'000'000'000'000ULL;

TEST(ReplayWindow, AcceptsEachSequenceOnceWithinTheWindowAndNothingOlder) {
  ReplayWindow w;
  w.begin_epoch(7);
  EXPECT_EQ(w.epoch(), 7U);
  EXPECT_TRUE(w.accept(1, kT0, kT0).ok());
  EXPECT_EQ(w.accept(1, kT0, kT0).error().code, Errc::refused);
  EXPECT_TRUE(w.accept(1, kT0 + 10, kT0).ok());
  EXPECT_TRUE(w.accept(1, kT0 + 5, kT0).ok()) << "reordered within the window";
  EXPECT_EQ(w.accept(1, kT0 + 5, kT0).error().code, Errc::refused);
  EXPECT_TRUE(w.accept(1, kT0 + 1000, kT0).ok());
  EXPECT_EQ(w.accept(1, kT0 + 10, kT0).error().code, Errc::refused) << "older than the window";
  EXPECT_TRUE(w.accept(2, kT0, kT0).ok()) << "each sender its own window";
}

TEST(ReplayWindow, ANewEpochForgetsEveryWindowAndEmptiesTheSenderTable) {
  ReplayWindow w;
  w.begin_epoch(1);
  for (std::uint32_t s = 1; s <= kMaxSenders; ++s) ASSERT_TRUE(w.accept(s, kT0, kT0).ok());
  const Status full = w.accept(kMaxSenders + 1, kT0, kT0);
  ASSERT_FALSE(full.ok());
  EXPECT_EQ(full.error().code, Errc::capacity_exceeded) << "a full table is said as such, not as a replay";
  EXPECT_EQ(w.senders(), kMaxSenders);
  w.begin_epoch(2);
  EXPECT_EQ(w.senders(), 0U);
  EXPECT_TRUE(w.accept(kMaxSenders + 1, kT0, kT0).ok()) << "the restart retired the old senders";
  // A sender's clock may be behind its previous station's: in a new epoch its window starts afresh.
  EXPECT_TRUE(w.accept(1, kT0 - 1'000'000'000ULL, kT0).ok());
}

}  // namespace
}  // namespace rescue::app::protocol
