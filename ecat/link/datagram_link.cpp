#include "ecat/link/datagram_link.hpp"

#include <cstring>

namespace rescue::ecat {
namespace {

// The returned frame carries the datagrams that were sent, in order, with the same lengths.
bool same_datagrams(const FrameView& sent, const FrameView& back) noexcept {
  if (sent.datagram_count() != back.datagram_count()) return false;
  auto s = sent.begin();
  auto b = back.begin();
  for (std::size_t i = 0; i < sent.datagram_count(); ++i, ++s, ++b) {
    const DatagramView ds = *s;
    const DatagramView db = *b;
    if (ds.command() != db.command() || ds.length() != db.length() || ds.index() != db.index()) return false;
  }
  return true;
}

}  // namespace

FrameBuilder& DatagramLink::begin() noexcept {
  ++index_;
  builder_.reset(kMasterMac);
  sent_ = ConstByteSpan{};
  return builder_;
}

Result<FrameView> DatagramLink::exchange(hal::Nanoseconds deadline) noexcept {
  return exchange(ExchangeDeadlines{deadline, deadline});
}

Result<FrameView> DatagramLink::exchange(const ExchangeDeadlines& deadlines) noexcept {
  const Status sent = send_frame();
  if (!sent.ok()) return sent.error();
  if (ring_ == nullptr) return await_frame(deadlines.receive);
  // The clock read on a line of its own: rt_verify resolves this virtual call by the name at its location.
  const hal::Nanoseconds sends_ended = nic_.clock().now();
  return await_merged(after_held_sends(deadlines, sends_ended));
}

ExchangeDeadlines DatagramLink::after_held_sends(const ExchangeDeadlines& deadlines, hal::Nanoseconds now) noexcept {
  if (deadlines.period <= 0 || now < deadlines.receive) return deadlines;
  // The host held the master in its sends (over veth: the main copy's send returned 74-829 us late
  // in the cycle a fault command fell in) until past the receive deadline: the copies left late, and
  // a repeat would not fit before the next period's send. Their time moves on by whole periods: the
  // next send is missed only if they are not back before it (the caller skips the periods passed).
  const hal::Nanoseconds moved = ((now - deadlines.receive) / deadlines.period + 1) * deadlines.period;
  return ExchangeDeadlines{deadlines.receive + moved, deadlines.repeat_limit + moved, deadlines.period};
}

Result<FrameView> DatagramLink::exchange_within(hal::Nanoseconds timeout) noexcept {
  const Status sent = send_frame();
  if (!sent.ok()) return sent.error();
  // The wait is measured from the moment the frame left: a process preempted between preparing the
  // exchange and sending it (a slow host, not a slow network) must not use up the frame's timeout.
  const hal::Nanoseconds deadline = nic_.clock().now() + timeout;
  return ring_ != nullptr ? await_merged(ExchangeDeadlines{deadline, deadline}) : await_frame(deadline);
}

Status DatagramLink::send_frame() noexcept {
  ++stats_.exchanges;
  if (ring_ != nullptr) returns_ = CopyReturns{};
  sent_ = builder_.finish();
  const Result<FrameView> sent_view = FrameView::parse(sent_);
  if (!sent_view.ok() || sent_view.value().datagram_count() == 0) {
    return make_error(Errc::invalid_argument, "exchange of an empty frame");
  }
  sent_view_ = sent_view.value();
  return send_sent();
}

Status DatagramLink::send_sent() noexcept {
  if (tap_ != nullptr) tap_(tap_context_, sent_, nic_.clock().now(), TapDirection::outbound);
  sent_at_[index_] = nic_.clock().now();
  expected_wkc_[index_] = expected_wkc_next_;
  expected_wkc_next_ = 0;
  const Status sent = nic_.send(sent_);
  if (!sent.ok()) {
    ++stats_.send_errors;
    return sent.error();
  }
  if (ring_ != nullptr) {
    const Result<std::size_t> copy = make_ring_copy(sent_, ByteSpan(ring_tx_));
    if (!copy.ok() || !ring_->send(ConstByteSpan(ring_tx_.data(), copy.value())).ok()) ++stats_.ring_send_errors;
  }
  return Status::success();
}

bool DatagramLink::take_copy(Port on, std::size_t length) noexcept {
  const ConstByteSpan frame(scratch_.data(), length);
  if (tap_ != nullptr) tap_(tap_context_, frame, nic_.clock().now(), TapDirection::inbound);
  const Result<FrameView> view = FrameView::parse(frame);
  if (!view.ok()) {
    ++stats_.malformed;
    return false;
  }
  if (view.value().datagram_count() == 0 || (*view.value().begin()).index() != index_) {
    note_stale(view.value());
    // A copy not waited for came back after all (late): wait for it again from now on.
    (is_ring_copy(frame) ? expect_ring_ : expect_main_) = true;
    return false;
  }
  // A second copy of the same kind (the same frame twice) is ignored: the first one counts.
  if (!returns_.main_back && !returns_.ring_back) first_back_at_ = nic_.clock().now();
  if (is_ring_copy(frame)) {
    if (returns_.ring_back) return false;
    returns_.ring_back = true;
    returns_.ring_on = on;
    std::memcpy(ring_back_.data(), frame.data(), length);
    ring_back_length_ = length;
  } else {
    if (returns_.main_back) return false;
    returns_.main_back = true;
    returns_.main_on = on;
    std::memcpy(main_back_.data(), frame.data(), length);
    main_back_length_ = length;
  }
  return true;
}

Result<FrameView> DatagramLink::await_merged(const ExchangeDeadlines& deadlines) noexcept {
  const hal::Nanoseconds limit = deadlines.repeat_limit > deadlines.receive ? deadlines.repeat_limit : deadlines.receive;
  const hal::Nanoseconds reserve = repeat_reserve();
  const hal::Nanoseconds decide_by = limit - reserve < deadlines.receive ? limit - reserve : deadlines.receive;
  Result<FrameView> first = await_copies(deadlines.receive, decide_by);
  if (!first.ok()) return first;
  note_round_trip(first_back_at_ - sent_at_[index_]);
  // Closed while in flight: the ring copy went round the ring, the main copy did not.
  const bool closed_in_flight =
      returns_.ring_back && returns_.ring_on == Port::main && !(returns_.main_back && returns_.main_on == Port::ring);
  if (!closed_in_flight || nic_.clock().now() >= limit) return first;
  return repeat_after_repair(first.value(), ExchangeDeadlines{deadlines.receive, limit});
}

Result<FrameView> DatagramLink::repeat_after_repair(const FrameView& first, const ExchangeDeadlines& deadlines) noexcept {
  const ConstByteSpan first_bytes = first.bytes();  // in rx_, which the repeat's merge overwrites
  std::memcpy(first_merged_.data(), first_bytes.data(), first_bytes.size());
  const ByteSpan first_merged(first_merged_.data(), first_bytes.size());
  first_returns_ = returns_;
  const ConstByteSpan original = sent_;
  const std::uint16_t expected_wkc = expected_wkc_[index_];
  const Result<std::size_t> repeat = make_repeat(original, ByteSpan(repeat_tx_), static_cast<std::uint8_t>(index_ + 1));
  const auto first_again = [&]() -> Result<FrameView> {
    std::memcpy(rx_.data(), first_merged_.data(), first_merged.size());
    returns_ = first_returns_;
    return FrameView::parse(ConstByteSpan(rx_.data(), first_merged.size()));
  };
  if (!repeat.ok() || repeat.value() == 0) return first_again();
  ++index_;
  ++stats_.ring_repeats;
  sent_ = ConstByteSpan(repeat_tx_.data(), repeat.value());
  const Result<FrameView> repeat_view = FrameView::parse(sent_);
  if (!repeat_view.ok()) return first_again();
  sent_view_ = repeat_view.value();
  expected_wkc_[index_] = expected_wkc;
  if (ring_ == nullptr || !send_sent().ok()) return first_again();  // ring_: only a redundant link repeats
  // Each copy is expected as it was in the first frame (a copy back round the ring waits for the other
  // anyway): a master port cut in flight loses the repeat's copy there too. No repeat follows this
  // one, so a copy back round the ring has the other waited for until the repeat limit (past the
  // receive deadline: a host that held the first copies must not leave the repeat too little time).
  const Result<FrameView> again = await_copies(deadlines.repeat_limit, deadlines.repeat_limit);
  if (!again.ok()) return first_again();
  const CopyCounters repeat_counters = returns_.counters;
  CopyCounters merged_counters = first_returns_.counters;
  if (!take_repeated(again.value(), repeat_counters, first_merged, merged_counters).ok()) return first_again();
  returns_.counters = merged_counters;
  // The datagrams not repeated keep the first frame's answers, and what its lost copy took with it.
  returns_.copy_lost = returns_.copy_lost || first_returns_.copy_lost;
  first_returns_ = returns_;
  return first_again();
}

hal::Nanoseconds DatagramLink::round_copy_due(hal::Nanoseconds now, hal::Nanoseconds deadline) const noexcept {
  // Both copies left together and a closed ring is the same length both ways: the other copy is due
  // within the round trip the first one took (at least kRingPollSlice), counted from its return.
  const hal::Nanoseconds round_trip = now - sent_at_[index_];
  const hal::Nanoseconds due = now + (round_trip > kRingPollSlice ? round_trip : kRingPollSlice);
  return due < deadline ? due : deadline;
}

hal::Nanoseconds DatagramLink::repeat_reserve() const noexcept {
  // Twice the quickest: the repeat's own round trip varies with where the cycle falls (106-128 us
  // on the simulated robot at 100 Mbit/s), and the host may hold its copies a little too.
  return 2 * quickest_round_trip_[sent_.size() / kRoundTripBand];
}

void DatagramLink::note_round_trip(hal::Nanoseconds round_trip) noexcept {
  hal::Nanoseconds& quickest = quickest_round_trip_[sent_.size() / kRoundTripBand];
  if (round_trip > 0 && (quickest == 0 || round_trip < quickest)) quickest = round_trip;
}

Result<FrameView> DatagramLink::await_copies(hal::Nanoseconds deadline, hal::Nanoseconds decide_by) noexcept {
  returns_ = CopyReturns{};
  const bool may_repeat = sent_.data() != repeat_tx_.data();  // the frame awaited is not the repeat itself
  hal::Clock& time = nic_.clock();
  // Both NICs are looked at without waiting; when neither had a copy, the NIC where a missing copy
  // came back last time is waited on for at most kRingPollSlice. Bounded: each turn either takes a
  // frame or moves the clock on. Ends when the copies expected (those that came back last time) are
  // in, after one more look at both NICs. A copy back round the ring (on the other NIC) says the ring
  // was closed when it went: the other copy, sent with it, is then waited for whether expected or
  // not, but only until it is due (round_copy_due) when a repeat may follow: not back by then, it was
  // lost in flight.
  hal::Nanoseconds wait_until = deadline;
  for (;;) {
    bool took = false;
    for (const Port port : {Port::main, Port::ring}) {
      hal::Nic& port_nic = port == Port::main ? nic_ : *ring_;
      const Result<std::size_t> got = port_nic.receive(ByteSpan(scratch_), time.now());
      if (got.ok()) {
        took = true;
        (void)take_copy(port, got.value());
      } else if (got.error().code != Errc::timeout) {
        return got.error();
      }
    }
    if (returns_.main_back && returns_.ring_back) break;
    const bool main_round = returns_.main_back && returns_.main_on == Port::ring;
    const bool ring_round = returns_.ring_back && returns_.ring_on == Port::main;
    if (main_round || ring_round) {
      if (may_repeat && wait_until == deadline) {
        const hal::Nanoseconds back_at = time.now();  // its own statement: rt_verify reads the virtual call's name here
        const hal::Nanoseconds due = round_copy_due(back_at, deadline);
        // Not past the time a repeat must be decided by (but one more look at both NICs first).
        wait_until = due < decide_by ? due : (decide_by > back_at ? decide_by : back_at);
      }
    } else if ((returns_.main_back || !expect_main_) && (returns_.ring_back || !expect_ring_)) {
      break;
    }
    if (took) continue;
    const hal::Nanoseconds now = time.now();
    if (now >= wait_until) break;
    const hal::Nanoseconds slice_end = now + kRingPollSlice < wait_until ? now + kRingPollSlice : wait_until;
    // Wait where the copy still missing came back last time (the main copy's first).
    const Port wait_on = !returns_.main_back && (expect_main_ || returns_.ring_back) ? main_came_on_ : ring_came_on_;
    const Result<std::size_t> got = (wait_on == Port::main ? nic_ : *ring_).receive(ByteSpan(scratch_), slice_end);
    if (got.ok()) {
      (void)take_copy(wait_on, got.value());
    } else if (got.error().code != Errc::timeout) {
      return got.error();
    }
  }
  // A copy lost in flight: the main copy while the ring copy went round the closed ring (the main
  // copy passed every slave), or a copy expected back (not a master port's cut) while the other
  // turned at a break (it passed the slaves on its side). The ring copy of a closed ring passes no
  // processing unit: lost, it loses no answer.
  const bool main_round = returns_.main_back && returns_.main_on == Port::ring;
  const bool ring_round = returns_.ring_back && returns_.ring_on == Port::main;
  returns_.copy_lost = (!returns_.main_back && (ring_round || expect_main_)) ||
                       (!returns_.ring_back && !main_round && expect_ring_);
  // What to wait for next time: the copies that came back (both again when none did).
  if (returns_.main_back) main_came_on_ = returns_.main_on;
  if (returns_.ring_back) ring_came_on_ = returns_.ring_on;
  expect_main_ = returns_.main_back || !returns_.ring_back;
  expect_ring_ = returns_.ring_back || !returns_.main_back;
  if (!returns_.main_back && !returns_.ring_back) {
    ++stats_.timeouts;
    return make_error(Errc::timeout, "no copy of the frame came back on either NIC");
  }
  const Result<FrameView> main_view = FrameView::parse(ConstByteSpan(main_back_.data(), main_back_length_));
  const Result<FrameView> ring_view = FrameView::parse(ConstByteSpan(ring_back_.data(), ring_back_length_));
  Result<FrameView> merged =
      merge_copies(sent_view_, returns_.main_back && main_view.ok() ? &main_view.value() : nullptr,
                   returns_.ring_back && ring_view.ok() ? &ring_view.value() : nullptr, ByteSpan(rx_), returns_.counters);
  if (!merged.ok()) {
    ++stats_.malformed;
    return make_error(Errc::malformed, "returned frame differs from the frame sent", index_);
  }
  return merged;
}

void DatagramLink::note_stale(const FrameView& view) noexcept {
  ++stats_.stale_frames;
  if (view.datagram_count() == 0) return;
  const hal::Nanoseconds age = nic_.clock().now() - sent_at_[(*view.begin()).index()];
  if (age > stats_.stale_age_max) stats_.stale_age_max = age;
  if (age > kSoemReceiveTimeout) return;
  ++stats_.stale_within_2ms;
  const std::uint16_t expected = expected_wkc_[(*view.begin()).index()];
  std::uint32_t wkc = 0;
  // cppcheck-suppress useStlAlgorithm ; frame views have no standard iterators
  for (const DatagramView d : view) wkc += d.command() == Command::LRW ? d.wkc() : 0U;
  if (expected != 0 && wkc >= expected) ++stats_.stale_within_2ms_full_wkc;
}

Result<FrameView> DatagramLink::await_frame(hal::Nanoseconds deadline) noexcept {
  for (;;) {
    const Result<std::size_t> got = nic_.receive(ByteSpan(rx_), deadline);
    if (!got.ok()) {
      if (got.error().code == Errc::timeout) ++stats_.timeouts;
      return got.error();
    }
    const ConstByteSpan frame(rx_.data(), got.value());
    if (tap_ != nullptr) tap_(tap_context_, frame, nic_.clock().now(), TapDirection::inbound);
    const Result<FrameView> view = FrameView::parse(frame);
    if (!view.ok()) {
      ++stats_.malformed;
      continue;
    }
    if (view.value().datagram_count() == 0 || (*view.value().begin()).index() != index_) {
      note_stale(view.value());
      continue;
    }
    if (!same_datagrams(sent_view_, view.value())) {
      ++stats_.malformed;
      return make_error(Errc::malformed, "returned frame differs from the frame sent", index_);
    }
    return view.value();
  }
}

unsigned DatagramLink::most_sends(hal::Nanoseconds timeout, unsigned attempts) const noexcept {
  if (attempts <= 1 || repeat_silence_ <= 0) return attempts;
  const hal::Nanoseconds step = timeout > 0 ? timeout : 1;
  const hal::Nanoseconds more = repeat_silence_ / step + 1;
  constexpr hal::Nanoseconds kMostMore = 100000;  // a silence of seconds over a timeout of microseconds
  return attempts + static_cast<unsigned>(more < kMostMore ? more : kMostMore);
}

bool DatagramLink::may_give_up(hal::Nanoseconds first_sent, unsigned sends, unsigned attempts) const noexcept {
  if (sends < attempts) return false;
  if (attempts <= 1) return true;
  return nic_.clock().now() - first_sent >= repeat_silence_;
}

Result<FrameView> DatagramLink::exchange(hal::Nanoseconds timeout, unsigned attempts) noexcept {
  Result<FrameView> back = make_error(Errc::timeout, "no frame came back", attempts);
  const hal::Nanoseconds first_sent = nic_.clock().now();
  const unsigned most = most_sends(timeout, attempts);
  for (unsigned sends = 0; sends < most && !may_give_up(first_sent, sends, attempts); ++sends) {
    back = exchange_within(timeout);
    if (back.ok() || back.error().code != Errc::timeout) break;
  }
  return back;
}

Result<std::uint16_t> DatagramLink::transfer(Command command, std::uint32_t address, ByteSpan data,
                                             hal::Nanoseconds timeout, unsigned attempts) noexcept {
  if (data.size() > kMaxDatagramDataLength) return make_error(Errc::invalid_argument, "transfer too long");
  const auto length = static_cast<std::uint16_t>(data.size());
  Error last = make_error(Errc::timeout, "no frame came back", attempts);
  const hal::Nanoseconds first_sent = nic_.clock().now();
  const unsigned most = most_sends(timeout, attempts);
  for (unsigned sends = 0; sends < most && !may_give_up(first_sent, sends, attempts); ++sends) {
    FrameBuilder& frame = begin();
    const Result<DatagramSlot> slot =
        frame.add(command, index_, address, length, writes_slave(command) ? ConstByteSpan(data) : ConstByteSpan{});
    if (!slot.ok()) return slot.error();
    const Result<FrameView> back = exchange_within(timeout);
    if (!back.ok()) {
      last = back.error();
      if (last.code == Errc::timeout) continue;
      return last;
    }
    const DatagramView d = *back.value().begin();
    if (reads_slave(command) && length > 0) std::memcpy(data.data(), d.data().data(), length);
    return d.wkc();
  }
  return last;
}

Result<StreamOutcome> DatagramLink::stream(Command command, std::uint32_t address, ByteSpan data, unsigned count,
                                           unsigned in_flight, hal::Nanoseconds timeout) noexcept {
  if (data.size() > kMaxDatagramDataLength) return make_error(Errc::invalid_argument, "transfer too long");
  if (ring_ != nullptr) return stream_redundant(command, address, data, count, timeout);
  const auto length = static_cast<std::uint16_t>(data.size());
  const unsigned window = in_flight == 0 ? 1 : (in_flight > kMaxStreamInFlight ? kMaxStreamInFlight : in_flight);
  // The frames on their way, oldest first: their index and when each was sent.
  std::array<std::uint8_t, kMaxStreamInFlight> index_of{};
  std::array<hal::Nanoseconds, kMaxStreamInFlight> sent_at{};
  unsigned head = 0;
  unsigned flying = 0;
  unsigned sent = 0;
  StreamOutcome outcome;
  while (outcome.returned + outcome.lost < count) {
    while (sent < count && flying < window) {
      FrameBuilder& frame = begin();
      const Result<DatagramSlot> slot =
          frame.add(command, index_, address, length, writes_slave(command) ? ConstByteSpan(data) : ConstByteSpan{});
      if (!slot.ok()) return slot.error();
      const Status out = send_frame();
      if (!out.ok()) return out.error();
      const unsigned at = (head + flying) % kMaxStreamInFlight;
      index_of[at] = index_;
      sent_at[at] = nic_.clock().now();
      ++flying;
      ++sent;
    }
    const Result<std::size_t> got = nic_.receive(ByteSpan(rx_), sent_at[head] + timeout);
    if (!got.ok()) {
      if (got.error().code != Errc::timeout) return got.error();
      ++stats_.timeouts;  // the oldest is lost
      head = (head + 1) % kMaxStreamInFlight;
      --flying;
      ++outcome.lost;
      continue;
    }
    const ConstByteSpan bytes(rx_.data(), got.value());
    if (tap_ != nullptr) tap_(tap_context_, bytes, nic_.clock().now(), TapDirection::inbound);
    const Result<FrameView> view = FrameView::parse(bytes);
    if (!view.ok() || view.value().datagram_count() == 0) {
      ++stats_.malformed;
      continue;
    }
    const DatagramView d = *view.value().begin();
    // Which frame on its way it is; those sent before it that are still missing are lost.
    unsigned k = 0;
    while (k < flying && index_of[(head + k) % kMaxStreamInFlight] != d.index()) ++k;
    if (k == flying) {
      ++stats_.stale_frames;
      continue;
    }
    if (view.value().datagram_count() != 1 || d.command() != command || d.length() != length) {
      ++stats_.malformed;
      return make_error(Errc::malformed, "returned frame differs from the frame sent", d.index());
    }
    stats_.timeouts += k;
    outcome.lost += k;
    head = (head + k + 1) % kMaxStreamInFlight;
    flying -= k + 1;
    ++outcome.returned;
    outcome.last_wkc = d.wkc();
    outcome.last_back_at = nic_.clock().now();
    if (reads_slave(command) && length > 0) std::memcpy(data.data(), d.data().data(), length);
  }
  return outcome;
}

// Redundant: one frame at a time (its copies come back on either NIC), each merged.
Result<StreamOutcome> DatagramLink::stream_redundant(Command command, std::uint32_t address, ByteSpan data,
                                                     unsigned count, hal::Nanoseconds timeout) noexcept {
  const auto length = static_cast<std::uint16_t>(data.size());
  StreamOutcome outcome;
  for (unsigned i = 0; i < count; ++i) {
    FrameBuilder& frame = begin();
    const Result<DatagramSlot> slot =
        frame.add(command, index_, address, length, writes_slave(command) ? ConstByteSpan(data) : ConstByteSpan{});
    if (!slot.ok()) return slot.error();
    const Result<FrameView> back = exchange_within(timeout);
    if (!back.ok()) {
      if (back.error().code != Errc::timeout) return back.error();
      ++outcome.lost;
      continue;
    }
    const DatagramView d = *back.value().begin();
    ++outcome.returned;
    outcome.last_wkc = d.wkc();
    outcome.last_back_at = nic_.clock().now();
    if (reads_slave(command) && length > 0) std::memcpy(data.data(), d.data().data(), length);
  }
  return outcome;
}

}  // namespace rescue::ecat
