#include "drivers/sim/segment/simulated_nic.hpp"

#include <algorithm>
#include <cstring>

namespace rescue::drivers {

Status SimulatedNic::send(ConstByteSpan frame) noexcept {
  if (frame.size() < ecat::kEthernetHeaderSize || frame.size() > kMaxFrame) {
    ++stats_.send_errors;
    return make_error(Errc::invalid_argument, "frame length", static_cast<std::uint32_t>(frame.size()));
  }
  const hal::Nanoseconds sent_at = std::max(clock_.now(), wire_free_at_);
  const std::size_t wire_bytes = std::max(frame.size(), ecat::kMinFrameSize) + kWireOverheadBytes + kInterFrameGapBytes;
  wire_free_at_ = sent_at + static_cast<hal::Nanoseconds>(wire_bytes) * kNsPerByte;
  ++stats_.frames_sent;
  if (peer_ != nullptr) {
    send_paired(frame, sent_at);
    return Status::success();
  }

  if (count_ == kQueueDepth) {
    // The receive ring is full: the frame still goes round the segment, its answer is lost.
    std::array<std::uint8_t, kMaxFrame> scratch{};
    std::memcpy(scratch.data(), frame.data(), frame.size());
    (void)segment_.process(ByteSpan(scratch.data(), frame.size()), sent_at, port_);
    ++stats_.frames_dropped;
    return Status::success();
  }
  Pending& slot = queue_[(head_ + count_) % kQueueDepth];
  std::memcpy(slot.bytes.data(), frame.data(), frame.size());
  slot.length = frame.size();
  const Result<FrameOutcome> outcome = segment_.process(ByteSpan(slot.bytes.data(), slot.length), sent_at, port_);
  if (outcome.ok() && outcome.value().returned) {
    slot.ready_at = outcome.value().last_bit_back;
    ++count_;
  }
  return Status::success();
}

void SimulatedNic::send_paired(ConstByteSpan frame, hal::Nanoseconds sent_at) noexcept {
  std::memcpy(scratch_.data(), frame.data(), frame.size());
  const ByteSpan in_flight(scratch_.data(), frame.size());
  const Result<FrameOutcome> outcome = segment_.process(in_flight, sent_at, port_);
  if (!outcome.ok() || !outcome.value().returned) return;
  SimulatedNic& back_on = outcome.value().port == port_ ? *this : *peer_;
  back_on.enqueue(in_flight, outcome.value().last_bit_back);
}

void SimulatedNic::enqueue(ConstByteSpan frame, hal::Nanoseconds ready_at) noexcept {
  if (count_ == kQueueDepth) {
    ++stats_.frames_dropped;  // the receive ring of the port it came back to is full
    return;
  }
  Pending& slot = queue_[(head_ + count_) % kQueueDepth];
  std::memcpy(slot.bytes.data(), frame.data(), frame.size());
  slot.length = frame.size();
  slot.ready_at = ready_at;
  ++count_;
}

SimulatedNicPair::SimulatedNicPair(SimulatedSegment& segment, hal::Clock& clock, hal::Nanoseconds receive_spin) noexcept
    : main_(segment, clock, MasterPort::main, receive_spin), ring_(segment, clock, MasterPort::ring, receive_spin) {
  if (!segment.has_ring()) {
    status_ = make_error(Errc::invalid_argument, "ring NICs on a segment without a ring cable");
    return;
  }
  main_.peer_ = &ring_;
  ring_.peer_ = &main_;
}

Result<std::size_t> SimulatedNic::receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept {
  while (count_ > 0 && queue_[head_].ready_at <= deadline) {
    Pending& front = queue_[head_];
    head_ = (head_ + 1) % kQueueDepth;
    --count_;
    // Empty again: the next frame goes to the first slot, whose lines are still in the cache,
    // rather than round all sixteen (24 KiB) one per cycle. The order of frames is unchanged.
    if (count_ == 0) head_ = 0;
    wait_until(front.ready_at);
    const auto frame = ConstByteSpan(front.bytes.data(), front.length);
    // Only EtherCAT frames that fit are handed over (the hal::Nic contract).
    const bool ethercat = front.length >= ecat::kEthernetHeaderSize &&
                          (load_be16(front.bytes.data() + 12) == ecat::kEtherTypeEtherCAT ||
                           load_be16(front.bytes.data() + 12) == ecat::kEtherTypeVlan);
    if (!ethercat || frame.size() > buffer.size()) {
      ++stats_.frames_dropped;
      continue;
    }
    std::memcpy(buffer.data(), frame.data(), frame.size());
    ++stats_.frames_received;
    return frame.size();
  }
  clock_.sleep_until(deadline);
  segment_.advance_to(clock_.now());
  ++stats_.receive_timeouts;
  return make_error(Errc::timeout, "no frame before the deadline");
}

void SimulatedNic::wait_until(hal::Nanoseconds at) noexcept {
  const hal::Nanoseconds start = clock_.now();
  if (receive_spin_ > 0 && at - start <= receive_spin_) {
    // Spin: the frame is due back sooner than a sleep would wake up. A clock that does not move by
    // itself (a virtual clock) is left to sleep_until, which moves it.
    for (unsigned unchanged = 0; unchanged < kSpinReadsOfAStillClock;) {
      const hal::Nanoseconds now = clock_.now();
      if (now >= at) return;
      unchanged = now == start ? unchanged + 1 : 0;
    }
  }
  clock_.sleep_until(at);
}

}  // namespace rescue::drivers
