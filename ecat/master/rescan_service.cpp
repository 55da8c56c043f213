// The operator's rescan in the cycle frame (rescan_service.hpp).
#include "ecat/master/rescan_service.hpp"

#include <algorithm>

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kSiiBlockLength = 14;  // 0x0502..0x050F: control, address, data
constexpr std::uint16_t kMaxFrames = 1000;     // a rescan whose frames keep getting lost ends here

std::uint32_t pair_at(const std::array<std::uint16_t, kRescanWords>& w, std::size_t word) noexcept {
  const std::size_t i = word - sii::kStationAlias;
  return static_cast<std::uint32_t>(w[i]) | (static_cast<std::uint32_t>(w[i + 1]) << 16U);
}

void copy_name(std::array<char, kMaxDeviceNameLength + 1>& out, const char* name) noexcept {
  std::size_t n = 0;
  for (; name != nullptr && name[n] != '\0' && n < kMaxDeviceNameLength; ++n) out[n] = name[n];
  out[n] = '\0';
}

}  // namespace

bool RescanService::any_identifying() const noexcept {
  return std::any_of(ctx_.slaves.begin(), ctx_.slaves.end(),
                     [](const SlaveRecord& s) { return s.recovery.state() == RecoveryState::identifying; });
}

RescanService::Refusal RescanService::request() noexcept {
  if (state_ != State::idle) return Refusal::busy;
  if (ctx_.state != MasterState::op) return Refusal::not_cycling;
  if (any_identifying()) return Refusal::recovering;
  status_ = RescanStatus::ok;
  counted_ = 0;
  devices_ = 0;
  count_answered_ = false;
  count_tries_ = 0;
  frames_ = 0;
  identified_ = 0;
  rotate_ = 0;
  words_read_.fill(0);
  misses_.fill(0);
  polling_.fill(false);
  match_ = NetworkMatch{};
  state_ = State::counting;
  return Refusal::none;
}

bool RescanService::take() noexcept {
  if (state_ != State::done) return false;
  state_ = State::idle;
  return true;
}

void RescanService::add_datagrams(CycleFrame& frame) noexcept {
  if (state_ != State::counting && state_ != State::identifying) return;
  ++frames_;
  if (state_ == State::counting) {
    if (frame.fits(kDatagramOverhead + 2)) (void)frame.add(*this, kCountTag, Command::BRD, make_address(0, reg::kType), 2);
    return;
  }
  if (any_identifying()) {  // the recovery reads a slave's SII from this frame on: no second reader
    status_ = RescanStatus::recovering;
    return finish();
  }
  std::size_t added = 0;
  for (std::size_t k = 0; k < devices_ && added < kDevicesPerFrame; ++k) {
    const std::size_t i = (rotate_ + k) % devices_;
    if (!device_open(i)) continue;
    if (!frame.fits(kDatagramOverhead + kSiiBlockLength)) break;  // the next frame, then
    const std::uint16_t adp = position_adp(static_cast<std::uint16_t>(i));
    if (polling_[i]) {
      (void)frame.add(*this, static_cast<std::uint8_t>(i), Command::APRD, make_address(adp, reg::kSiiControl),
                      kSiiBlockLength);
    } else {
      std::array<std::uint8_t, 6> command{};
      store_le16(command.data(), reg::kSiiCommandRead);
      store_le32(command.data() + 2, static_cast<std::uint32_t>(sii::kStationAlias + words_read_[i]));
      (void)frame.add(*this, static_cast<std::uint8_t>(i | kCommandTag), Command::APWR,
                      make_address(adp, reg::kSiiControl), 6, ConstByteSpan(command));
    }
    ++added;
  }
  rotate_ = devices_ == 0 ? 0 : (rotate_ + 1) % devices_;
}

void RescanService::on_answer(std::uint8_t tag, const DatagramView& d) noexcept {
  if (tag == kCountTag) {
    if (state_ != State::counting) return;
    counted_ = static_cast<std::uint8_t>(std::min<std::uint16_t>(d.wkc(), 0xFF));
    devices_ = std::min<std::size_t>(d.wkc(), kMaxFoundSlaves);
    count_answered_ = true;
    return;
  }
  const std::size_t i = tag & (kCommandTag - 1U);
  if (state_ != State::identifying || i >= devices_ || !device_open(i)) return;
  if (d.wkc() != 1) {
    ++misses_[i];  // nobody (or more than one device) at that place: again, up to kMaxMisses
    return;
  }
  if ((tag & kCommandTag) != 0) {
    polling_[i] = true;
    return;
  }
  if (d.data().size() < kSiiBlockLength) return;
  const std::uint8_t* data = d.data().data();
  const std::uint16_t control = load_le16(data);
  if ((control & reg::kSiiBusy) != 0) {
    ++misses_[i];  // poll again (a SII that stays busy is given up)
    return;
  }
  polling_[i] = false;
  if ((control & reg::kSiiCommandError) != 0) {
    ++misses_[i];  // command refused: issued again
    return;
  }
  const std::size_t got = (control & reg::kSiiRead8Bytes) != 0 ? 4 : 2;
  for (std::size_t k = 0; k < got && words_read_[i] < kRescanWords; ++k) {
    words_[i][words_read_[i]++] = load_le16(data + 6 + 2 * k);
  }
  misses_[i] = 0;
  if (words_read_[i] >= kRescanWords) identified_ |= std::uint32_t{1} << i;
}

void RescanService::end_exchange(hal::Nanoseconds /*now*/) noexcept {
  if (state_ != State::counting) return;
  if (count_answered_) {
    state_ = State::identifying;
    if (devices_ == 0) finish();
  } else if (++count_tries_ >= kMaxCountTries) {
    status_ = RescanStatus::incomplete;
    finish();
  }
}

void RescanService::settle(CycleResult& /*result*/) noexcept {
  if (state_ != State::identifying) return;
  bool open = false;
  for (std::size_t i = 0; i < devices_; ++i) open = open || device_open(i);
  if (!open || frames_ >= kMaxFrames) finish();
}

void RescanService::finish() noexcept {
  for (std::size_t i = 0; i < devices_; ++i) {
    FoundSlave& f = found_[i];
    f = FoundSlave{};
    if ((identified_ & (std::uint32_t{1} << i)) == 0) {
      copy_name(f.name, "not identified");
      continue;
    }
    const auto& w = words_[i];
    f.station_alias = w[0];
    f.vendor_id = pair_at(w, sii::kVendorId);
    f.product_code = pair_at(w, sii::kProductCode);
    f.revision = pair_at(w, sii::kRevision);
    f.serial_number = pair_at(w, sii::kSerial);
    // A planned slave of the same type names it (SlavePlan::device_name is the device type's name).
    const auto* type = std::find_if(ctx_.plan.begin(), ctx_.plan.end(), [&f](const SlavePlan& s) {
      return s.vendor_id == f.vendor_id && s.product_code == f.product_code;
    });
    copy_name(f.name, type != ctx_.plan.end() ? type->device_name : "unknown device");
  }
  const std::uint32_t all = devices_ >= 32 ? 0xFFFFFFFFU : (std::uint32_t{1} << devices_) - 1U;
  if (status_ == RescanStatus::ok && identified_ != all) status_ = RescanStatus::incomplete;
  if (status_ == RescanStatus::ok) {
    // Lost slaves (and what is behind them) may be absent without shifting the others; each one
    // that did not answer is then named missing, one that answers again is no difference.
    const SlaveMask lost = ctx_.monitor.lost() & ~ctx_.options.held_out & kAllSlaves;
    match_ = match_network(ctx_.plan, found(), ctx_.options.held_out | lost);
    for (std::size_t k = match_.differences.size(); k-- > 0;) {
      const NetworkDifference& d = match_.differences[k];
      if (d.kind == DifferenceKind::known_lost_present && d.planned < kMaxSlaves && (lost & slave_bit(d.planned)) != 0) {
        match_.differences.erase_at(k);
      }
    }
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if ((lost & slave_bit(p)) == 0 || (match_.present & slave_bit(p)) != 0) continue;
      (void)match_.differences.push_back(NetworkDifference{DifferenceKind::missing, static_cast<std::uint8_t>(p), kNoPosition});
    }
  }
  state_ = State::done;
}

}  // namespace rescue::ecat
