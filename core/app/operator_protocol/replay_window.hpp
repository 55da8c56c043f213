// The replay window of the UDP protocol (docs/protocol.md "Replay protection"): per sender, the
// highest sequence accepted and a 64-bit bitmap of the 64 sequences below it (RFC 4303 section
// 3.4.3's sliding window), all of it per epoch.
//
// The epoch is what makes it fail closed. It is a random 64-bit number drawn at every start of the
// socket handler (protocol_auth.hpp new_epoch(): libsodium's randombytes); every datagram carries
// the epoch it was made for inside the authenticated header, and a datagram of any other epoch is
// refused. A datagram recorded before a restart (of the robot or of its socket handler process)
// names an epoch that no longer exists, so it is refused whatever the sender's clock says, and
// there is no file whose loss, damage or deletion could reopen it: the window lives in memory only
// and dies with its epoch. Stations learn the epoch from the robot (get_epoch, answered with the
// station's own sequence echoed) before they send a request.
//
// A key holder could otherwise lock a sender out for the whole epoch with one datagram (sequence
// 2^64-1) or take every slot: a sequence more than kMaxSequenceLeadNs ahead of the robot's own
// clock is refused (stations number their requests by their Unix time in ns), so such a lockout
// lasts at most that long; and one slot is kept for kOperatorSender (ctl's default --sender), so
// other senders can never fill the table against it. The socket handler asks the window only for
// well-formed requests (docs/protocol.md "Senders", docs/security.md "What is not defended").
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/containers/fixed_vector.hpp"

namespace rescue::app::protocol {

constexpr std::size_t kMaxSenders = 16;
constexpr std::uint64_t kWindowSize = 64;
constexpr std::uint32_t kOperatorSender = 1;                       // its slot is never taken by another
constexpr std::uint64_t kMaxSequenceLeadNs = 600'000'000'000ULL;  // 10 min ahead of the robot's clock

class ReplayWindow {
 public:
  // A new epoch (nonzero): every sender's window is forgotten, the sender table emptied.
  void begin_epoch(std::uint64_t epoch) noexcept;
  std::uint64_t epoch() const noexcept { return epoch_; }

  // Accepts `sequence` from `sender` once in this epoch, never again; `robot_unix_ns` is the robot's
  // wall clock. Errors: refused (replayed or older than the window), out_of_range (more than
  // kMaxSequenceLeadNs ahead of `robot_unix_ns`), capacity_exceeded (no slot for a new sender: the
  // table is full, or only kOperatorSender's kept slot is left).
  Status accept(std::uint32_t sender, std::uint64_t sequence, std::uint64_t robot_unix_ns) noexcept;

  std::size_t senders() const noexcept { return windows_.size(); }

 private:
  struct Window {
    std::uint32_t sender{0};
    std::uint64_t highest{0};  // highest accepted
    std::uint64_t seen{0};     // bit i: highest - i was accepted
  };

  FixedVector<Window, kMaxSenders> windows_;
  std::uint64_t epoch_{0};
};

}  // namespace rescue::app::protocol
