// The replay window (docs/protocol.md "Replay protection"): a sequence is accepted once; older than
// the window, never; and after a restart from the persisted file, nothing accepted before is
// accepted again, while the limit is written only once per block, not per message.
#include <gtest/gtest.h>

#include <array>
#include <cstring>

#include "core/app/operator_protocol/replay_window.hpp"

namespace rescue::app::protocol {
namespace {

class MemoryStore final : public ReplayStore {
 public:
  Result<std::size_t> load(ByteSpan out) noexcept override {
    if (size == 0) return make_error(Errc::not_found, "none");
    std::memcpy(out.data(), bytes.data(), size);
    return size;
  }
  Status write_limits(ConstByteSpan in) noexcept override {
    if (fail) return make_error(Errc::io_error, "disk full");
    std::memcpy(bytes.data(), in.data(), in.size());
    size = in.size();
    ++saves;
    return Status::success();
  }
  std::array<std::uint8_t, kReplayFileMaxSize> bytes{};
  std::size_t size{0};
  int saves{0};
  bool fail{false};
};

constexpr std::uint64_t kT0 = 1'700'000'000'000'000'000ULL;

TEST(ReplayWindow, AcceptsOnceWithinTheWindow) {
  MemoryStore store;
  ReplayWindow w(store);
  EXPECT_FALSE(w.restore(kT0).file_status.ok());
  EXPECT_TRUE(w.accept(1, kT0).ok());
  EXPECT_EQ(w.accept(1, kT0).error().code, Errc::refused);
  EXPECT_TRUE(w.accept(1, kT0 + 10).ok());
  EXPECT_TRUE(w.accept(1, kT0 + 5).ok()) << "out of order within the window";
  EXPECT_EQ(w.accept(1, kT0 + 5).error().code, Errc::refused);
  EXPECT_TRUE(w.accept(2, kT0).ok()) << "windows are per sender";
  EXPECT_TRUE(w.accept(1, kT0 + 1000).ok());
  EXPECT_EQ(w.accept(1, kT0 + 1000 - kWindowSize).error().code, Errc::refused) << "older than the window";
  EXPECT_EQ(store.saves, 2) << "one durable write per sender per block, not per message";
}

TEST(ReplayWindow, RestartDoesNotReopenOldMessages) {
  MemoryStore store;
  {
    ReplayWindow w(store);
    (void)w.restore(kT0);
    for (std::uint64_t i = 0; i < 100; ++i) ASSERT_TRUE(w.accept(9, kT0 + i * 1000).ok());
  }
  ReplayWindow again(store);
  const RestoreOutcome r = again.restore(kT0);
  ASSERT_TRUE(r.file_status.ok());
  EXPECT_EQ(r.senders, 1U);
  for (std::uint64_t i = 0; i < 100; ++i) EXPECT_EQ(again.accept(9, kT0 + i * 1000).error().code, Errc::refused);
  EXPECT_EQ(again.accept(9, kT0 + kPersistBlock).error().code, Errc::refused) << "the whole persisted block";
  EXPECT_TRUE(again.accept(9, kT0 + kPersistBlock + 1).ok());
}

TEST(ReplayWindow, DamagedFileStartsAtTheRobotsClockAndFailedWriteAcceptsNothing) {
  MemoryStore store;
  store.bytes[0] = 'X';
  store.size = 24;
  ReplayWindow w(store);
  EXPECT_FALSE(w.restore(kT0).file_status.ok());
  EXPECT_EQ(w.accept(3, kT0 - 1).error().code, Errc::refused) << "stamped before the restart";
  EXPECT_TRUE(w.accept(3, kT0 + kPersistBlock + 1).ok());
  store.fail = true;
  EXPECT_EQ(w.accept(3, kT0 + 10 * kPersistBlock).error().code, Errc::io_error);
  EXPECT_EQ(w.accept(4, kT0 + 10 * kPersistBlock).error().code, Errc::io_error);
  EXPECT_EQ(w.senders(), 1U) << "a sender whose first message failed takes no slot";
}

TEST(ReplayWindow, FileDecoderChecksEveryByte) {
  PersistedLimits limits;
  ASSERT_TRUE(limits.push_back(PersistedLimit{1, 42}));
  std::array<std::uint8_t, kReplayFileMaxSize> buf{};
  const Result<std::size_t> n = encode_replay_file(limits, ByteSpan(buf));
  ASSERT_TRUE(n.ok());
  ASSERT_TRUE(decode_replay_file(ConstByteSpan(buf.data(), n.value())).ok());
  for (std::size_t byte = 0; byte < n.value(); ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      buf[byte] ^= static_cast<std::uint8_t>(1U << bit);
      EXPECT_FALSE(decode_replay_file(ConstByteSpan(buf.data(), n.value())).ok()) << byte << ":" << bit;
      buf[byte] ^= static_cast<std::uint8_t>(1U << bit);
    }
  }
  EXPECT_FALSE(decode_replay_file(ConstByteSpan(buf.data(), n.value() - 1)).ok());
}

}  // namespace
}  // namespace rescue::app::protocol
