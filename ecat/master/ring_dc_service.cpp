// DC across a break of the ring: latch, read, then the ring-side time writes every cycle.
#include "ecat/master/ring_dc_service.hpp"

#include "core/base/endian.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/link/redundant_merge.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kLatchLength = 4;
constexpr std::uint16_t kTimeLength = 8;

// The ring reaches slaves behind a break when it is open (or split) and the ring port reaches one.
bool has_ring_side(const RingStatus& s) noexcept {
  return (s.state == RingState::open || s.state == RingState::lost) && s.after < kMaxSlaves;
}

}  // namespace

void RingDcService::reset() noexcept {
  status_ = RingDcStatus{};
  behind_ = 0;
  to_read_ = 0;
  last_reference_ = 0;
  anchor_reference_ = 0;
  reference_.set_reference_behind_break(false);
}

void RingDcService::begin(std::uint8_t after) noexcept {
  status_.phase = RingDcPhase::latch;
  status_.after = after;
  status_.written = 0;
  const std::size_t reference = ctx_.reference_position();
  status_.reference_behind_break = reference < kMaxSlaves && reference >= after;
  reference_.set_reference_behind_break(status_.reference_behind_break);
  // The ring plan's positions are in processing order (drivers/joint/robot_ring_network_plan.hpp):
  // the ring port reaches `after` and every position after it.
  behind_ = 0;
  const SlaveMask reachable = ctx_.dc_slaves & ctx_.present() & ~ctx_.monitor.out_of_exchange();
  for (std::size_t p = after; p < kMaxSlaves; ++p) {
    if ((reachable & slave_bit(p)) != 0 && p != reference) behind_ |= slave_bit(p);
  }
  // The reads of the path change with it: the reference's time from before the change is not its
  // time on the new path (it is read by another copy when it lies behind the break).
  last_reference_ = 0;
}

void RingDcService::add_datagrams(CycleFrame& frame) noexcept {
  frame_time_ = ctx_.now();
  if (status_.phase == RingDcPhase::idle) return;
  switch (status_.phase) {
    case RingDcPhase::latch: {
      static constexpr std::array<std::uint8_t, kLatchLength> kZero{};
      if (frame.fits(kDatagramOverhead + kLatchLength)) {
        (void)frame.add(*this, kLatchTag, Command::BWR, make_address(0, reg::kDcReceiveTimePort0), kLatchLength,
                        ConstByteSpan(kZero.data(), kZero.size()));
      }
      break;
    }
    case RingDcPhase::read: add_reads(frame); break;
    case RingDcPhase::write: add_writes(frame); break;
    case RingDcPhase::idle: break;
  }
}

void RingDcService::add_reads(CycleFrame& frame) noexcept {
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((to_read_ & slave_bit(p)) == 0) continue;
    if (!frame.fits(kDatagramOverhead + kReadLength)) return;
    (void)frame.add(*this, static_cast<std::uint8_t>(p), Command::FPRD,
                    make_address(ctx_.plan[p].station_address, reg::kDcReceiveTimeEpu), kReadLength);
  }
}

void RingDcService::add_writes(CycleFrame& frame) noexcept {
  const std::uint64_t reference = predicted_reference();
  if (reference == 0 || behind_ == 0) return;
  // Round robin from where the last frame stopped, so that every slave is written when not all fit.
  for (std::size_t n = 0; n < kMaxSlaves; ++n) {
    const std::size_t p = (next_write_ + n) % kMaxSlaves;
    if ((behind_ & slave_bit(p)) == 0) continue;
    if (!frame.fits(kDatagramOverhead + kTimeLength)) {
      next_write_ = p;
      return;
    }
    std::array<std::uint8_t, kTimeLength> time{};
    store_le64(time.data(), reference + static_cast<std::uint64_t>(lead_[p]));
    if (frame.add(*this, kWriteTag, Command::NOP, ring_side_time_write_address(ctx_.plan[p].station_address), kTimeLength,
                  ConstByteSpan(time.data(), time.size()))) {
      ++status_.writes;
    }
  }
  next_write_ = 0;
}

void RingDcService::on_answer(std::uint8_t tag, const DatagramView& d) noexcept {
  if (tag == kWriteTag) return;  // no answer to act on: the written clock's 0x092C tells
  if (tag == kLatchTag) {
    if (status_.phase == RingDcPhase::latch && d.wkc() != 0) {
      status_.phase = RingDcPhase::read;
      // The copies of the latch frame as they were sent (this frame's: its answer is being read).
      latch_spacing_ = ring_port_.last_sent_at() > 0 ? ring_port_.last_sent_at() - reference_copy_sent_at() : 0;
      const std::size_t reference = ctx_.reference_position();
      to_read_ = behind_ | (reference < kMaxSlaves ? slave_bit(reference) : 0);
    }
    return;
  }
  if (status_.phase != RingDcPhase::read || tag >= kMaxSlaves || d.length() < kReadLength) return;
  const SlaveMask bit = slave_bit(tag);
  if ((to_read_ & bit) == 0) return;
  to_read_ &= ~bit;
  if (d.wkc() == 0) {
    behind_ &= ~bit;  // not reachable on the new path (a second break): nothing to write to
    return;
  }
  const std::uint8_t* data = d.data().data();
  passage_[tag] = load_le64(data) + load_le64(data + 8);
  delay_[tag] = load_le32(data + 16);
}

void RingDcService::finish_calibration() noexcept {
  const std::size_t reference = ctx_.reference_position();
  if (reference >= kMaxSlaves) {
    status_.phase = RingDcPhase::idle;
    return;
  }
  const std::uint64_t reference_passage = passage_[reference];
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((behind_ & slave_bit(p)) == 0) continue;
    lead_[p] = static_cast<std::int64_t>(passage_[p] - reference_passage) - static_cast<std::int64_t>(delay_[p]) -
               latch_spacing_;
  }
  status_.written = behind_;
  status_.phase = RingDcPhase::write;
  ++status_.calibrations;
  next_write_ = 0;
}

double RingDcService::rate_excess() const noexcept {
  // From the first read on: the longer the baseline, the less a frame's send jitter weighs in it.
  const hal::Nanoseconds baseline = last_reference_at_ - anchor_at_;
  if (baseline < kMinRateBaseline) return 0.0;
  const auto advanced = static_cast<std::int64_t>(last_reference_ - anchor_reference_);
  return static_cast<double>(advanced - baseline) / static_cast<double>(baseline);
}

std::uint64_t RingDcService::predicted_reference() const noexcept {
  if (last_reference_ == 0) return 0;
  const hal::Nanoseconds elapsed = frame_time_ - last_reference_at_;
  const auto excess = static_cast<std::int64_t>(static_cast<double>(elapsed) * rate_excess());
  return last_reference_ + static_cast<std::uint64_t>(elapsed + excess);
}

hal::Nanoseconds RingDcService::reference_copy_sent_at() const noexcept {
  const hal::Nanoseconds sent = status_.reference_behind_break ? ring_port_.last_sent_at() : main_port_.last_sent_at();
  return sent > 0 ? sent : frame_time_;
}

void RingDcService::before_ring_send(ByteSpan frame, hal::Nanoseconds now) noexcept {
  if (!patches_ring_copies() || last_reference_ == 0) return;
  const hal::Nanoseconds waited = now - frame_time_;
  if (waited == 0) return;
  const auto shift = waited + static_cast<std::int64_t>(static_cast<double>(waited) * rate_excess());
  const Result<MutableFrameView> view = MutableFrameView::parse(frame);
  if (!view.ok()) return;
  for (const MutableDatagramView d : view.value()) {
    if (d.command() != Command::FPWR || d.ado() != reg::kDcSystemTime || d.length() != kTimeLength) continue;
    const ByteSpan time = d.data();
    store_le64(time.data(), load_le64(time.data()) + static_cast<std::uint64_t>(shift));
  }
}

void RingDcService::settle(CycleResult& /*result*/) noexcept {
  const RingStatus& ring = ring_.monitor().status();
  if (!ctx_.link.redundant() || !has_ring_side(ring)) {
    if (status_.phase != RingDcPhase::idle) {
      status_.phase = RingDcPhase::idle;
      status_.written = 0;
      behind_ = 0;
      status_.reference_behind_break = false;
      reference_.set_reference_behind_break(false);
    }
  } else if (status_.phase == RingDcPhase::idle || ring.after != status_.after) {
    begin(ring.after);
  }
  const std::uint64_t read = reference_.frame_reference_time();
  if (read != 0) {
    last_reference_ = read;
    last_reference_at_ = reference_copy_sent_at();
    if (anchor_reference_ == 0) {
      anchor_reference_ = read;
      anchor_at_ = last_reference_at_;
    }
  }
  if (status_.phase == RingDcPhase::read && to_read_ == 0) finish_calibration();
}

}  // namespace rescue::ecat
