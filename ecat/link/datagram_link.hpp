// The master's side of the wire: build a frame, send it, wait for it to come back, and hand back
// the returned datagrams. Used for every exchange, bring-up (one blocking transfer at a time,
// with retries) and cyclic (one frame per cycle with the caller's deadline).
//
// A returned frame is recognised by its datagrams' index byte (all datagrams of a frame carry
// the frame's index, a counter); a frame that comes back late, after its exchange gave up, is
// dropped and counted when it turns up, never mistaken for the current one. The returned frame
// must have the datagrams that were sent (count, commands, lengths), else it is refused.
//
// Cable redundancy (set_ring): with a second NIC every frame also goes out on it as its ring copy
// (redundant_merge.hpp), the copies are collected from both NICs by index until both are back or
// the deadline passes, and the exchange returns their merge. A copy that did not come back last
// time (a break at a master port) is not waited for: the exchange ends once the others are in,
// after one more look at both NICs, so a cut at a port does not hold every cycle to its deadline;
// such a copy turning up late (stale) makes the next exchanges wait for it again. A copy back round
// the ring (on the other NIC: the ring was closed when it went) has the other copy waited for,
// expected or not, but only until it is due (round_copy_due); not back by then, it was lost in
// flight. A ring closed while the frame was in flight (the ring copy came back round the ring, the
// main copy did not: it turned at the break or was lost at a master port cut in flight) leaves
// slaves in neither copy: the exchange's repeatable datagrams are sent again at once under a new
// index, and their answers taken (redundant_merge.hpp, make_repeat). A copy that may have passed
// slaves and did not come back (a damaged main copy of the closed ring: the ring copy comes back
// round it unprocessed) is marked in copy_returns().copy_lost: the answers no returned copy counted
// were carried out unseen (answer_lost_with_a_copy). The repeat has its own time
// (ExchangeDeadlines): a host that held the first copies until near the receive deadline must not
// cost the cycle, so the repeat is sent and waited for until the caller's repeat limit, which may
// lie past the receive deadline. And the wait for the other copy once one came back round the ring
// ends early enough for the repeat to fit before that limit (repeat_reserve: twice the quickest
// round trip seen of a frame that long), even when the host held the first copy for most of it.
// Without a ring NIC nothing changes.
//
// Frame tap: every frame sent and every frame received (even a late one) is also handed to an
// optional tap, e.g. the capture writer recording a pcapng file (ecat/capture/capture_tap.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/link/redundant_merge.hpp"
#include "hal/net/nic.hpp"

namespace rescue::ecat {

enum class TapDirection : std::uint8_t { outbound, inbound };
// Called with each frame the link sends or receives, and the NIC clock's time.
using FrameTapFn = void (*)(void* context, ConstByteSpan frame, hal::Nanoseconds time, TapDirection direction) noexcept;

// What DatagramLink::stream() did.
struct StreamOutcome {
  unsigned returned{0};       // frames that came back
  unsigned lost{0};           // frames that did not (within the timeout of their sending)
  std::uint16_t last_wkc{0};  // of the last frame that came back
  hal::Nanoseconds last_back_at{0};  // when it was received (NIC clock)
};

// A cyclic exchange's deadlines (NIC clock). Its copies are waited for until `receive`. A repeat
// after a ring change in flight (redundant links only) is sent when the first copies show it before
// `repeat_limit` (taken as at least `receive`), and its copies are waited for until `repeat_limit`.
// `period` (0: none) is the cycle's, for a host that held the master in its sends (redundant links
// only): sent past `receive`, both deadlines move on by whole periods (the caller skips the periods
// the exchange runs past), so that a ring change that fell between the two sends is still repeated.
struct ExchangeDeadlines {
  hal::Nanoseconds receive{0};
  hal::Nanoseconds repeat_limit{0};
  hal::Nanoseconds period{0};
};

// SOEM's EC_TIMEOUTRET: how long its ec_receive_processdata waits for a frame (for comparisons).
constexpr hal::Nanoseconds kSoemReceiveTimeout = 2 * hal::kNsPerMs;

struct LinkStats {
  std::uint64_t exchanges{0};
  std::uint64_t timeouts{0};        // no matching frame before the deadline
  std::uint64_t stale_frames{0};    // frames of earlier exchanges that came back late
  hal::Nanoseconds stale_age_max{0};  // the latest of them: from its sending to its turning up
  // Of those, the ones back within kSoemReceiveTimeout of their sending: what a master that waits
  // that long for its frame whatever its period would have received; the rest were held longer.
  std::uint64_t stale_within_2ms{0};
  // Of those, the ones whose process data (LRW) working counters added up to what the master expected
  // when it sent them (expect_process_data_wkc): cycles SOEM's way of counting calls valid.
  std::uint64_t stale_within_2ms_full_wkc{0};
  std::uint64_t malformed{0};       // frames that did not parse or did not match what was sent
  std::uint64_t send_errors{0};
  std::uint64_t ring_send_errors{0};  // ring copies the ring NIC refused (the main copy still went)
  // Exchanges sent again because the ring closed while their frame was in flight (await_copies).
  std::uint64_t ring_repeats{0};
};

class DatagramLink {
 public:
  // Source MAC of the frames the master sends (the ESCs do not care; captures show it).
  static constexpr MacAddress kMasterMac{0x02, 0x52, 0x4D, 0x00, 0x00, 0x01};

  explicit DatagramLink(hal::Nic& nic) noexcept : nic_(nic) {}

  void set_tap(FrameTapFn tap, void* context) noexcept {
    tap_ = tap;
    tap_context_ = context;
  }

  // Cable redundancy: every frame from now on also goes out on `ring` (nullptr: main NIC only).
  // Between exchanges only; `ring` must share the main NIC's clock.
  void set_ring(hal::Nic* ring) noexcept { ring_ = ring; }
  bool redundant() const noexcept { return ring_ != nullptr; }
  hal::Nic* ring_nic() noexcept { return ring_; }
  // Where the copies of the last exchange came back, and each datagram's counter in each copy.
  const CopyReturns& copy_returns() const noexcept { return returns_; }
  // While a copy is awaited, the NIC it came back on last time is waited on for at most this long
  // before both are looked at again (hal::Nic waits on one NIC): a copy on the other NIC waits this
  // much at most.
  static constexpr hal::Nanoseconds kRingPollSlice = 20 * hal::kNsPerUs;

  // Starts a new frame; datagrams are added with index() as their index.
  FrameBuilder& begin() noexcept;
  // The sum of the LRW working counters the frame being built should come back with (0: none),
  // kept with its index when it is sent, so that a late frame can be told whole (stats()).
  void expect_process_data_wkc(std::uint16_t total) noexcept { expected_wkc_next_ = total; }
  std::uint8_t index() const noexcept { return index_; }

  // Sends the frame built since begin() and waits for it until `deadline` (NIC clock). The view
  // points into the link's receive buffer and stays valid until the next begin().
  Result<FrameView> exchange(hal::Nanoseconds deadline) noexcept;
  // The same, with a repeat after a ring change in flight allowed until deadlines.repeat_limit.
  Result<FrameView> exchange(const ExchangeDeadlines& deadlines) noexcept;

  // The same, sending the frame again (same index) when nothing came back within `timeout` of its
  // sending, up to `attempts` times: for bring-up exchanges whose datagrams may be repeated. With
  // more than one attempt it gives up only once the link has also been silent for repeat_silence()
  // since the first send (sending again every `timeout`, at most repeat_silence / timeout + 1 more).
  Result<FrameView> exchange(hal::Nanoseconds timeout, unsigned attempts) noexcept;

  // How long a repeated blocking exchange (above, and transfer() with more than one attempt) waits
  // for any answer before it gives up, on top of its attempts. Over veth the segment is a process:
  // a simulator the host does not run for a few ms is slowness, not silence, and a bring-up must not
  // fail on it (issue 35: `run --check` failed at identify after 3 x 2 ms under load, 8 late frames
  // came back). A real segment answers in microseconds, so only a dead one waits this out.
  // 0 (the default): give up after the attempts alone. A single attempt is a probe whose caller
  // decides (the count step's first contact): never extended.
  void set_repeat_silence(hal::Nanoseconds silence) noexcept { repeat_silence_ = silence > 0 ? silence : 0; }
  hal::Nanoseconds repeat_silence() const noexcept { return repeat_silence_; }
  // The same rule for a caller's own repeat loop (station_io.hpp): the sends it may make, and whether
  // it may give up after `sends` timed out, its first sent at `first_sent`.
  unsigned most_sends(hal::Nanoseconds timeout, unsigned attempts) const noexcept;
  bool may_give_up(hal::Nanoseconds first_sent, unsigned sends, unsigned attempts) const noexcept;

  // One datagram in a frame of its own, sent up to `attempts` times while no frame comes back
  // (each attempt waits `timeout` from its sending). For reading commands the returned data is copied into `data`;
  // for writing ones `data` is what is sent. Returns the working counter.
  Result<std::uint16_t> transfer(Command command, std::uint32_t address, ByteSpan data, hal::Nanoseconds timeout,
                                 unsigned attempts = 3) noexcept;

  // `count` frames of one datagram each (the same command, address and data), sent without waiting
  // for the one before: at most `in_flight` (1..kMaxStreamInFlight) are on their way at a time, so
  // the wire, not the round trip, sets the pace (the static drift compensation's FRMW). A frame not
  // back within `timeout` of its sending is lost (counted, not repeated). For reading commands the
  // last returned frame's data is copied into `data`.
  static constexpr unsigned kMaxStreamInFlight = 8;
  Result<StreamOutcome> stream(Command command, std::uint32_t address, ByteSpan data, unsigned count, unsigned in_flight,
                               hal::Nanoseconds timeout) noexcept;

  hal::Clock& clock() noexcept { return nic_.clock(); }
  hal::Nic& nic() noexcept { return nic_; }
  const LinkStats& stats() const noexcept { return stats_; }

 private:
  Status send_frame() noexcept;                                     // the frame built since begin()
  Status send_sent() noexcept;  // sent_ (parsed into sent_view_) on the main NIC, its ring copy on the ring NIC
  Result<FrameView> await_frame(hal::Nanoseconds deadline) noexcept;  // its return, until `deadline`
  Result<FrameView> exchange_within(hal::Nanoseconds timeout) noexcept;
  // Redundant: both NICs, merged. A copy back round the ring has the other waited for until it is
  // due, and (when a repeat may follow) not past `decide_by`.
  Result<FrameView> await_copies(hal::Nanoseconds deadline, hal::Nanoseconds decide_by) noexcept;
  // When the copy still missing is due, once the other came back round the ring at `now` (at most `deadline`).
  hal::Nanoseconds round_copy_due(hal::Nanoseconds now, hal::Nanoseconds deadline) const noexcept;
  // The time to keep for a repeat of the frame sent (0: none seen of its length yet), and the record of round trips.
  hal::Nanoseconds repeat_reserve() const noexcept;
  void note_round_trip(hal::Nanoseconds round_trip) noexcept;
  // `deadlines` as they stand once the frame is sent at `now` (ExchangeDeadlines::period).
  static ExchangeDeadlines after_held_sends(const ExchangeDeadlines& deadlines, hal::Nanoseconds now) noexcept;
  // await_copies, and the repeat when the ring closed while the frame was in flight.
  Result<FrameView> await_merged(const ExchangeDeadlines& deadlines) noexcept;
  Result<FrameView> repeat_after_repair(const FrameView& first, const ExchangeDeadlines& deadlines) noexcept;
  // A received frame: true when it is a copy of the current exchange (kept), false when stale or malformed (counted).
  bool take_copy(Port on, std::size_t length) noexcept;
  void note_stale(const FrameView& view) noexcept;
  Result<StreamOutcome> stream_redundant(Command command, std::uint32_t address, ByteSpan data, unsigned count,
                                         hal::Nanoseconds timeout) noexcept;

  hal::Nic& nic_;
  FrameBuilder builder_{};
  std::array<std::uint8_t, kMaxFrameSize + kVlanTagSize + 4> rx_{};
  ConstByteSpan sent_{};
  FrameView sent_view_{};  // sent_, parsed by send_frame()
  std::uint8_t index_{0};
  hal::Nanoseconds repeat_silence_{0};  // set_repeat_silence()
  std::array<hal::Nanoseconds, 256> sent_at_{};  // when the frame of each index was last sent (stale ages)
  std::array<std::uint16_t, 256> expected_wkc_{};  // expect_process_data_wkc of each index's last frame
  std::uint16_t expected_wkc_next_{0};
  // Cable redundancy (set_ring): the ring NIC, the ring copy sent, the copies back, the merge.
  using FrameBuffer = std::array<std::uint8_t, kMaxFrameSize + kVlanTagSize + 4>;
  hal::Nic* ring_{nullptr};
  FrameBuffer ring_tx_{};
  FrameBuffer scratch_{};
  FrameBuffer main_back_{};
  FrameBuffer ring_back_{};
  std::size_t main_back_length_{0};
  std::size_t ring_back_length_{0};
  CopyReturns returns_{};
  FrameBuffer repeat_tx_{};     // the repeat after a repair in flight
  FrameBuffer first_merged_{};  // the first exchange's merge, while the repeat is out
  CopyReturns first_returns_{};
  // The quickest round trip seen (first copy back) of a frame of each length band (kRoundTripBand
  // bytes wide), 0 when none: what a repeat of that frame needs at least.
  static constexpr std::size_t kRoundTripBand = 64;
  std::array<hal::Nanoseconds, (kMaxFrameSize + kVlanTagSize + 4) / kRoundTripBand + 1> quickest_round_trip_{};
  hal::Nanoseconds first_back_at_{0};  // when the first copy of the exchange awaited came back
  bool expect_main_{true};  // the main copy came back last time: wait for it
  bool expect_ring_{true};
  Port main_came_on_{Port::ring};  // where each copy came back last time (a closed ring to begin with)
  Port ring_came_on_{Port::main};
  FrameTapFn tap_{nullptr};
  void* tap_context_{nullptr};
  LinkStats stats_{};
};

}  // namespace rescue::ecat
