// DC across a break of the ring: latch, read, then the island's time from its first clock every cycle.
#include "ecat/master/ring_dc_service.hpp"

#include <algorithm>
#include <cmath>

#include "core/base/endian.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/link/redundant_merge.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kLatchLength = 4;
constexpr std::uint16_t kTimeLength = 8;
constexpr std::uint16_t kDelayLength = 4;  // 0x0928
// Ways beyond this are not a ring's (its length is tens of microseconds): a bad read, dropped.
constexpr std::uint64_t kMaxWayNs = 1'000'000;
// The island reference's steering (RingDcService::steer): the cycles whose differences give the
// baseline and the noise, the filter's weight, the loop's gain per cycle, the largest step, and how
// far the filtered difference must stand from the baseline, in standard errors, before it is acted on.
constexpr std::uint32_t kBaselineCycles = 32;
constexpr double kFilterWeight = 1.0 / 16.0;
constexpr double kGain = 1.0 / 16.0;
// 4 ppm of slew at the 1 ms period: the island's followers lag a ramp of 4 ns a cycle by about
// 57 ns of 0x092C; at 8 ns they lagged 113-115 ns over veth (issue 34's bound is 100 ns).
constexpr double kMaxStepNs = 4.0;
constexpr double kClip = 3.0;       // a sample further than this many deviations from the filtered value is cut to it
// A drifting clock's difference is a ramp, and the filter lags a ramp by 16 cycles of it, about 0.6 of
// the clip whatever the rate (the baseline's deviation of a ramp is 9.2 cycles of it): a ramp is never
// cut. This many samples in a row cut on one side are a level the copies' transit moved to (over
// veth), not drift: the baseline is taken again there instead of steering the island reference to it.
constexpr std::uint32_t kLevelShiftSamples = 8;
constexpr double kSignificance = 4.0;
constexpr double kFloorNs = 5.0;  // below this nothing is steered (the simulator's ESC rounds to 1 ns)
// A dead band wider than this cannot keep a drive's SYNC0 within issue 34's 1 us (the loop acts only
// beyond it, and lags): with copies that noisy the steering would only chase the wander of their
// transit times (over veth: 2-876 ns steered on at least 10 of 240 breaks, none of it drift), so the island
// reference runs free on its learned rate instead.
constexpr double kUsefulBandNs = 250.0;

// The ring reaches slaves behind a break when it is open (or split) and the ring port reaches one.
bool has_ring_side(const RingStatus& s) noexcept {
  return (s.state == RingState::open || s.state == RingState::lost) && s.after < kMaxSlaves;
}

std::size_t first_of(SlaveMask mask) noexcept {
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((mask & slave_bit(p)) != 0) return p;
  }
  return kMaxSlaves;
}

}  // namespace

void RingDcService::reset() noexcept {
  status_ = RingDcStatus{};
  behind_ = 0;
  island_ = 0;
  to_read_ = 0;
  ways_to_write_ = 0;
  island_reference_ = kMaxSlaves;
  restart_baseline();
  reference_.set_reference_behind_break(false);
}

void RingDcService::begin(std::uint8_t after) noexcept {
  status_.phase = RingDcPhase::latch;
  status_.after = after;
  status_.written = 0;
  status_.island_reference = kMaxSlaves;
  island_ = 0;
  ways_to_write_ = 0;
  island_reference_ = kMaxSlaves;
  restart_baseline();
  const std::size_t reference = ctx_.reference_position();
  status_.reference_behind_break = reference < kMaxSlaves && reference >= after;
  reference_.set_reference_behind_break(status_.reference_behind_break);
  // The ring plan's positions are in processing order (drivers/joint/robot_ring_network_plan.hpp):
  // the ring port reaches `after` and every position after it, in that order.
  behind_ = 0;
  const SlaveMask reachable = ctx_.dc_slaves & ctx_.present() & ~ctx_.monitor.out_of_exchange();
  for (std::size_t p = after; p < kMaxSlaves; ++p) {
    if ((reachable & slave_bit(p)) != 0) behind_ |= slave_bit(p);
  }
}

void RingDcService::add_datagrams(CycleFrame& frame) noexcept {
  island_time_ = 0;
  room_ = frame.remaining();
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
    case RingDcPhase::island: add_island(frame); break;
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

void RingDcService::add_before_reference(CycleFrame& frame) noexcept {
  // What this service had last frame, restores included, less the island read and a margin.
  const std::size_t budget = room_ + restore_bytes_;
  restore_bytes_ = 0;
  if (status_.ways_set == 0) return;
  const SlaveMask present = ctx_.present();
  const std::size_t each = kDatagramOverhead + kDelayLength;
  const std::size_t needed = static_cast<std::size_t>(popcount(status_.ways_set)) * each;
  if (budget < needed + kDatagramOverhead + kTimeLength + CycleFrame::kMailboxReserve + 2 * each ||
      !frame.fits(needed)) {
    ++status_.restores_skipped;
    return;
  }
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((status_.ways_set & slave_bit(p)) == 0) continue;
    const SlaveMask up_to = slave_bit(p) | (slave_bit(p) - 1);
    if ((present & up_to) != up_to) {  // a position would name another slave
      ++status_.restores_skipped;
      continue;
    }
    std::array<std::uint8_t, kDelayLength> delay{};
    store_le32(delay.data(), delay_[p]);
    if (frame.add(*this, static_cast<std::uint8_t>(kRestoreTag | p), Command::APWR,
                  make_address(position_adp(static_cast<std::uint16_t>(p)), reg::kDcSystemTimeDelay), kDelayLength,
                  ConstByteSpan(delay.data(), delay.size()))) {
      restore_bytes_ += each;
    }
  }
}

void RingDcService::add_ways(CycleFrame& frame) noexcept {
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((ways_to_write_ & slave_bit(p)) == 0) continue;
    if (!frame.fits(kDatagramOverhead + kDelayLength)) return;
    std::array<std::uint8_t, kDelayLength> way{};
    store_le32(way.data(), way_[p]);
    status_.ways_set |= slave_bit(p);  // from the send on: it may land even if its answer is lost
    (void)frame.add(*this, static_cast<std::uint8_t>(kWayTag | p), Command::FPWR,
                    make_address(ctx_.plan[p].station_address, reg::kDcSystemTimeDelay), kDelayLength,
                    ConstByteSpan(way.data(), way.size()));
  }
}

void RingDcService::add_island(CycleFrame& frame) noexcept {
  if (island_reference_ >= kMaxSlaves) return;
  if (ways_to_write_ != 0) {
    add_ways(frame);
    return;  // no island read before every way is set: a clock would compare with its main delay
  }
  if (pending_step_ != 0 && frame.fits(kDatagramOverhead + kTimeLength)) {
    std::array<std::uint8_t, kTimeLength> offset{};
    offset_now_ -= static_cast<std::uint64_t>(pending_step_);
    store_le64(offset.data(), offset_now_);
    if (frame.add(*this, kOffsetTag, Command::FPWR,
                  make_address(ctx_.plan[island_reference_].station_address, reg::kDcSystemTimeOffset), kTimeLength,
                  ConstByteSpan(offset.data(), offset.size()))) {
      ++status_.steps;
      status_.steered_ns -= pending_step_;
    }
    pending_step_ = 0;
  }
  if (!frame.fits(kDatagramOverhead + kTimeLength)) {
    ++status_.island_skipped;
    return;
  }
  if (frame.add(*this, kIslandTag, Command::NOP, island_time_read_address(ctx_.plan[island_reference_].station_address),
                kTimeLength)) {
    ++status_.island_reads;
  }
}

void RingDcService::on_answer(std::uint8_t tag, const DatagramView& d) noexcept {
  if (tag == kIslandTag) {
    if (d.wkc() != 0 && d.length() >= kTimeLength) island_time_ = load_le64(d.data().data());
    return;
  }
  if (tag == kOffsetTag) return;  // the island reference's time tells
  if (tag >= kWayTag && tag < kWayTag + kMaxSlaves) {
    if (d.wkc() != 0) ways_to_write_ &= ~slave_bit(tag - kWayTag);
    return;
  }
  if (tag >= kRestoreTag && tag < kRestoreTag + kMaxSlaves) {
    if (d.wkc() != 0) status_.ways_set &= ~slave_bit(tag - kRestoreTag);  // the main copy reached it: restored
    return;
  }
  if (tag == kLatchTag) {
    if (status_.phase == RingDcPhase::latch && d.wkc() != 0) {
      status_.phase = RingDcPhase::read;
      latch_spacing_ = copy_spacing();
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
    behind_ &= ~bit;  // not reachable on the new path (a second break): not in the island
    return;
  }
  const std::uint8_t* data = d.data().data();
  passage_[tag] = load_le64(data) + load_le64(data + 8);
  offset_[tag] = load_le64(data + 8);
  delay_[tag] = load_le32(data + 16);
}

void RingDcService::finish_calibration() noexcept {
  const std::size_t reference = ctx_.reference_position();
  island_reference_ = status_.reference_behind_break ? reference : first_of(behind_);
  if (reference >= kMaxSlaves || island_reference_ >= kMaxSlaves) {
    status_.phase = RingDcPhase::idle;
    return;
  }
  // With the reference as island reference the ways are the main path's delays: nothing rewritten.
  rewrites_delays_ = island_reference_ != reference;
  island_ = behind_ & ~slave_bit(island_reference_);
  const std::uint64_t start = passage_[island_reference_];
  for (std::size_t p = 0; p < kMaxSlaves && rewrites_delays_; ++p) {
    if ((island_ & slave_bit(p)) == 0) continue;
    const std::uint64_t way = passage_[p] - start;
    if (passage_[p] < start || way > kMaxWayNs) {
      island_ &= ~slave_bit(p);  // latched before the island reference: not the ring copy's order
      ++status_.bad_ways;
      continue;
    }
    way_[p] = static_cast<std::uint32_t>(way);
  }
  ways_to_write_ = rewrites_delays_ ? island_ : 0;
  expected_ = static_cast<std::int64_t>(passage_[island_reference_] - passage_[reference]) - latch_spacing_;
  offset_now_ = offset_[island_reference_];
  restart_baseline();
  status_.steps = 0;
  status_.steered_ns = 0;
  status_.noise_ns = 0;
  status_.rebaselines = 0;
  status_.island_reference = static_cast<std::uint8_t>(island_reference_);
  status_.written = behind_;
  status_.phase = RingDcPhase::island;
  ++status_.calibrations;
}

hal::Nanoseconds RingDcService::copy_spacing() const noexcept {
  const hal::Nanoseconds main = main_port_.last_sent_at();
  const hal::Nanoseconds ring = ring_port_.last_sent_at();
  return main > 0 && ring > 0 ? ring - main : 0;
}

// The difference is held against its mean over the first kBaselineCycles cycles (the copies' mean
// transit difference, which no phase can be told from), filtered, and steered toward that mean only
// by what lies beyond a dead band of kSignificance deviations: the loop does not chase the copies' jitter.
void RingDcService::steer(std::int64_t difference) noexcept {
  const auto x = static_cast<double>(difference);
  if (samples_ < kBaselineCycles) {
    baseline_sum_ += x;
    baseline_square_sum_ += x * x;
    ++samples_;
    if (samples_ == kBaselineCycles) {
      const auto n = static_cast<double>(kBaselineCycles);
      baseline_ = baseline_sum_ / n;
      noise_ = std::max(kFloorNs, std::sqrt(std::max(0.0, baseline_square_sum_ / n - baseline_ * baseline_)));
      filtered_ = baseline_;
      status_.noise_ns = static_cast<std::int64_t>(std::llround(noise_));
    }
    return;
  }
  // The copies' outliers (a host stall of hundreds of microseconds) are cut, so that one of them
  // does not carry the filter past the threshold for many cycles.
  const double low = filtered_ - kClip * noise_;
  const double high = filtered_ + kClip * noise_;
  clipped_above_ = x > high ? clipped_above_ + 1 : 0;
  clipped_below_ = x < low ? clipped_below_ + 1 : 0;
  if (clipped_above_ >= kLevelShiftSamples || clipped_below_ >= kLevelShiftSamples) {
    restart_baseline();
    ++status_.rebaselines;
    return;
  }
  const double clipped = std::clamp(x, low, high);
  filtered_ += (clipped - filtered_) * kFilterWeight;
  const double deviation = filtered_ - baseline_;
  // Over veth the copies' difference does not only jitter: its mean wanders by about its deviation
  // over a break (measured, docs/redundancy.md), so the dead band is kSignificance deviations of
  // the samples themselves, and only what lies beyond it is steered.
  const double band = kSignificance * noise_;
  if (band > kUsefulBandNs) return;
  const double beyond = std::fabs(deviation) - band;
  if (beyond <= 0.0) return;
  const double signed_beyond = deviation > 0.0 ? beyond : -beyond;
  pending_step_ = static_cast<std::int64_t>(std::llround(std::clamp(signed_beyond * kGain, -kMaxStepNs, kMaxStepNs)));
}

void RingDcService::restart_baseline() noexcept {
  samples_ = 0;
  baseline_sum_ = 0.0;
  baseline_square_sum_ = 0.0;
  clipped_above_ = 0;
  clipped_below_ = 0;
  pending_step_ = 0;
}

void RingDcService::settle(CycleResult& /*result*/) noexcept {
  const RingStatus& ring = ring_.monitor().status();
  if (!ctx_.link.redundant() || !has_ring_side(ring)) {
    if (status_.phase != RingDcPhase::idle) {
      status_.phase = RingDcPhase::idle;
      status_.written = 0;
      status_.island_reference = kMaxSlaves;
      status_.steps = 0;
      status_.steered_ns = 0;
      status_.noise_ns = 0;
      status_.rebaselines = 0;
      behind_ = 0;
      island_ = 0;
      ways_to_write_ = 0;
      status_.reference_behind_break = false;
      reference_.set_reference_behind_break(false);
    }
  } else if (status_.phase == RingDcPhase::idle || ring.after != status_.after) {
    begin(ring.after);
  }
  if (status_.phase == RingDcPhase::read && to_read_ == 0) {
    finish_calibration();
  } else if (status_.phase == RingDcPhase::island && rewrites_delays_ && island_time_ != 0) {
    const std::uint64_t reference_time = reference_.frame_reference_time();
    if (reference_time != 0) {
      steer(static_cast<std::int64_t>(island_time_ - reference_time) - expected_ - copy_spacing());
    }
  }
}

}  // namespace rescue::ecat
