// The replay window of the UDP protocol (docs/protocol.md "Replay protection"): per sender, the
// highest sequence accepted and a 64-bit bitmap of the 64 sequences below it (RFC 4303 section
// 3.4.3's sliding window, as MAVLink 2 signing keeps a timestamp per link), plus a durable
// high-water mark so a restart does not reopen old messages.
//
// Durability without an fsync per message: before accepting a sequence above the persisted limit,
// the window writes limit = sequence + kPersistBlock to <state dir>/replay-window.bin (atomic and
// durable, hal/files/durable_file.hpp) and only then accepts. After a restart every sender's window
// starts at its persisted limit: everything at or below it is refused, so no message accepted
// before the restart (nor one that could have been) is accepted again. With sequences in ns of the
// sender's Unix time, the block is about one second: at most one write per sender per second, and
// after a restart a sender's messages are refused for at most about one second of its clock.
//
// A file that cannot be trusted (damaged, foreign) is not used: the window then starts every sender
// at the robot's wall clock (Unix ns) + kPersistBlock, which refuses every message stamped before
// the restart, as long as the senders' clocks are not ahead of the robot's. The decoder checks every
// byte (libFuzzer target fuzz_replay_window_file).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "core/containers/fixed_vector.hpp"

namespace rescue::app::protocol {

constexpr std::size_t kMaxSenders = 16;
constexpr std::uint64_t kWindowSize = 64;
constexpr std::uint64_t kPersistBlock = std::uint64_t{1} << 30;  // ~1.07 s of ns sequences
constexpr std::size_t kReplayFileHeaderSize = 16;
constexpr std::size_t kReplayFileRecordSize = 16;
constexpr std::size_t kReplayFileMaxSize = kReplayFileHeaderSize + kMaxSenders * kReplayFileRecordSize + 4;

struct PersistedLimit {
  std::uint32_t sender{0};
  std::uint64_t limit{0};  // every sequence <= limit is refused after a restart
};
using PersistedLimits = FixedVector<PersistedLimit, kMaxSenders>;

Result<std::size_t> encode_replay_file(const PersistedLimits& limits, ByteSpan out) noexcept;
// Errors: truncated, malformed, version, checksum, capacity_exceeded; no partial result is trusted.
Result<PersistedLimits> decode_replay_file(ConstByteSpan bytes) noexcept;

// Where the persisted limits go: the state directory in the firmware, memory in tests.
class ReplayStore {
 public:
  ReplayStore() = default;
  ReplayStore(const ReplayStore&) = delete;
  ReplayStore& operator=(const ReplayStore&) = delete;
  ReplayStore(ReplayStore&&) = delete;
  ReplayStore& operator=(ReplayStore&&) = delete;
  virtual ~ReplayStore() = default;
  // The file's bytes into `out`; not_found when there is none.
  virtual Result<std::size_t> load(ByteSpan out) noexcept = 0;
  // Durable replace; success means on disk.
  virtual Status write_limits(ConstByteSpan bytes) noexcept = 0;
};

// <dir>/replay-window.bin through hal::write_file_atomically / read_file_capped.
class FileReplayStore final : public ReplayStore {
 public:
  static constexpr const char* kFileName = "replay-window.bin";
  explicit FileReplayStore(const char* dir) noexcept;
  Result<std::size_t> load(ByteSpan out) noexcept override;
  Status write_limits(ConstByteSpan bytes) noexcept override;

 private:
  std::array<char, 512> dir_{};
};

struct RestoreOutcome {
  std::size_t senders{0};   // windows restored from the file
  Status file_status;       // success, not_found (fresh start) or why the file was not trusted
};

class ReplayWindow {
 public:
  explicit ReplayWindow(ReplayStore& store) noexcept : store_(&store) {}

  // Before the first accept(): the persisted limits, or the wall-clock floor (see above).
  RestoreOutcome restore(std::uint64_t wall_clock_unix_ns) noexcept;

  // Accepts `sequence` from `sender` once, never again. Errors: refused (replayed or older than the
  // window), capacity_exceeded (more senders than kMaxSenders), io_error (the limit could not be
  // made durable: the message is not accepted, because after a restart it could be again).
  Status accept(std::uint32_t sender, std::uint64_t sequence) noexcept;

  std::size_t senders() const noexcept { return windows_.size(); }
  std::uint32_t persist_writes() const noexcept { return persist_writes_; }

 private:
  struct Window {
    std::uint32_t sender{0};
    std::uint64_t highest{0};   // highest accepted (or the restored floor)
    std::uint64_t seen{0};      // bit i: highest - i was accepted
    std::uint64_t persisted{0}; // durable limit
  };
  Status persist(std::size_t changed, std::uint64_t limit) noexcept;

  ReplayStore* store_;
  FixedVector<Window, kMaxSenders> windows_;
  std::uint64_t floor_{0};  // a new sender's window starts here (0, or the wall-clock floor)
  std::uint32_t persist_writes_{0};
};

}  // namespace rescue::app::protocol
