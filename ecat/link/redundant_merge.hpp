// Cable redundancy: one frame goes out on both master ports (the main NIC and the ring NIC) and
// comes back as two copies; this file makes the ring copy and merges the copies into the one
// frame the master reads (docs/redundancy.md, "The merge").
//
// The ring copy is the main frame with the same index and the same datagrams, except:
//   - its source MAC ends in kRingCopyMacTail (the ESCs never touch it past the first byte), so a
//     copy tells which port it left by, whichever port it comes back on;
//   - its position-addressed datagrams (APRD/APWR/APRW/ARMW) and the reference clock's FRMW go as
//     NOP of the same length: from the ring port, position n means another slave, and an FRMW
//     entering behind a break would write an unread time into the clocks there;
//   - its ring-side time writes go as FPWR: a NOP addressed to a station's system time (0x0910) in
//     the main frame (no slave acts on a NOP) is, in the ring copy, an FPWR of that register with
//     the NOP's data. It feeds the clock of a slave behind a break, which only the ring copy
//     processes (DC across a break: ecat/master/ring_dc_service.hpp); with the ring closed the ring
//     copy processes no slave, so the write is void, whatever the state was when it was built;
//   - its island time reads go as FRMW: a NOP addressed to a station's 0x0918 in the main frame is,
//     in the ring copy, an FRMW of that station's 0x0910: the first clock behind a break gives its
//     time to the clocks after it within the ring copy, as the reference's FRMW does on the main path.
//
// The merge, per datagram:
//   working counter = main copy's + ring copy's (saturating at 0xFFFF);
//   data            = the main copy's bytes, and the ring copy's byte wherever the ring copy
//                     differs from the bytes sent.
// Why it is right: in a ring each slave processes exactly one of the copies (closed: the main copy
// passes every processing unit and the ring copy none; open between X and Y: the main copy reaches
// the slaves up to X, the ring copy those from Y), so a byte one slave wrote differs from the sent
// byte in that copy only. Limits: a slave writing the very byte that was sent is indistinguishable
// from no slave (harmless: the merged byte is the same); if both copies changed a byte (a broadcast
// read, BRD, answered by slaves on both sides: data ORed by each side) the ring copy's wins, so a
// BRD's data is that of the ring side only (its working counter is still the sum). Copies that do
// not carry the datagrams sent (count, lengths, index, command as sent or NOP) are refused.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat {

// The last byte of the ring copy's source MAC (the main copy's is DatagramLink::kMasterMac's, 0x01).
constexpr std::uint8_t kRingCopyMacTail = 0x02;
constexpr std::size_t kSourceMacTailOffset = 11;  // destination (6) + source bytes 0..4

// Whether `command` goes as NOP in the ring copy.
constexpr bool main_port_only(Command command) noexcept {
  return address_kind(command) == AddressKind::position || command == Command::FRMW;
}

// The ring-side time write of `station` (data: the system time it is to compare): a NOP in the
// main frame, an FPWR of 0x0910 in the ring copy.
constexpr std::uint32_t ring_side_time_write_address(std::uint16_t station) noexcept {
  return make_address(station, reg::kDcSystemTime);
}
constexpr bool is_ring_side_time_write(Command command, std::uint32_t address) noexcept {
  return command == Command::NOP && address_ado(address) == reg::kDcSystemTime;
}

// The island time read of `station` (the first clock behind a break): a NOP at the station's
// kIslandTimeMark in the main frame, an FRMW of its 0x0910 (8 bytes) in the ring copy. The mark is a
// register no FRMW goes to, so the NOP is told apart from a ring-side time write.
constexpr std::uint16_t kIslandTimeMark = reg::kDcReceiveTimeEpu;
constexpr std::uint32_t island_time_read_address(std::uint16_t station) noexcept {
  return make_address(station, kIslandTimeMark);
}
constexpr bool is_island_time_read(Command command, std::uint32_t address) noexcept {
  return command == Command::NOP && address_ado(address) == kIslandTimeMark;
}

// Writes the ring copy of `main` (a whole frame, as sent on the main NIC) into `out`; its length.
Result<std::size_t> make_ring_copy(ConstByteSpan main, ByteSpan out) noexcept;

// A cable repaired while a frame is in flight (docs/redundancy.md, "A cable changing while a frame is
// in flight"): the main copy turned at the break, the slaves before it processed; the ring copy, sent
// after the repair, went round the closed ring unprocessed. The slaves after the break are in neither
// copy (so too with the copies walked the other way round a cut: the ring copy round the still closed
// ring, the main copy turned at the cut or lost in the master's own cable), so the exchange is sent
// again at once, the datagrams that may be repeated only:
// the process data (LRD/LWR/LRW: the SyncManagers' buffers, written again with the same outputs, read
// again) and broadcast reads (BRD, the ring watch's count). Every other datagram goes as NOP in the
// repeat (a mailbox read or write, a register write, a position-addressed one, the reference clock's
// FRMW), its answer taken from the first frame.
constexpr bool repeatable(Command command) noexcept {
  return command == Command::LRD || command == Command::LWR || command == Command::LRW || command == Command::BRD;
}

// Writes the repeat of `sent` (a whole frame as sent on the main NIC) into `out` under `index`: the
// repeatable datagrams as sent, the others as NOP. Its length; 0 when it has no repeatable datagram.
Result<std::size_t> make_repeat(ConstByteSpan sent, ByteSpan out, std::uint8_t index) noexcept;

// Which port a returned copy left by: its source MAC's last byte.
bool is_ring_copy(ConstByteSpan frame) noexcept;

// Each datagram's working counter in each copy (0 for a copy that did not come back).
struct CopyCounters {
  std::array<std::uint16_t, kMaxDatagramsPerFrame> main{};
  std::array<std::uint16_t, kMaxDatagramsPerFrame> ring{};
  std::size_t datagrams{0};
};

// Where the copies of the last exchange came back (DatagramLink::copy_returns()): the ring state's
// evidence. A copy that came back on the other port than it left by went round a closed ring.
enum class Port : std::uint8_t { main, ring };
struct CopyReturns {
  bool main_back{false};        // the copy sent on the main NIC came back ...
  Port main_on{Port::main};     // ... on this NIC
  bool ring_back{false};        // the copy sent on the ring NIC came back ...
  Port ring_on{Port::ring};     // ... on this NIC
  // A copy that may have been processed by slaves did not come back (lost in flight, e.g. damaged
  // on a cable: its FCS broken): the main copy while the other went round the closed ring, or a
  // copy expected back (it came back last time) while the ring was open. The slaves that processed
  // it carried out its datagrams, unseen: see answer_lost_with_a_copy.
  bool copy_lost{false};
  CopyCounters counters{};
};

// A datagram of the exchange `returns` describes whose answer may have been lost with a copy: a
// copy was lost in flight and no copy that came back counted the datagram, so the slave may have
// carried it out in the lost one (a read of SM1 emptying its mailbox, a write of SM0 handing it a
// request). A service whose datagrams are not idempotent (the mailbox client) takes it as lost with
// its frame, as on a single port; on the ring the merged frame itself comes back (the other copy).
inline bool answer_lost_with_a_copy(const CopyReturns& returns, const DatagramView& datagram) noexcept {
  return returns.copy_lost && datagram.wkc() == 0;
}

// Merges the copies that came back (either may be null: it did not) into `out`, which receives the
// frame as sent on the main NIC with each datagram's merged data and working counter. `sent` is the
// main frame as sent. Returns the merged frame's view (into `out`).
Result<FrameView> merge_copies(const FrameView& sent, const FrameView* main_copy, const FrameView* ring_copy,
                               ByteSpan out, CopyCounters& counters) noexcept;

// Takes the repeat's answers into the first merge: each datagram the repeat carried (not a NOP in
// `repeat`, the repeat's merge) gets the repeat's data, working counter and per-copy counters.
// `first` is the first exchange's merged frame (as sent on the main NIC), in place.
Status take_repeated(const FrameView& repeat, const CopyCounters& repeat_counters, ByteSpan first,
                     CopyCounters& first_counters) noexcept;

}  // namespace rescue::ecat
