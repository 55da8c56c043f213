// Re-integration and re-arming, one datagram per cycle and slave.
#include "ecat/master/reintegration_service.hpp"

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/master/slave_config.hpp"

namespace rescue::ecat {
namespace {

constexpr hal::Nanoseconds kReintegrationTimeout = 3 * hal::kNsPerSec;
constexpr std::size_t kRearmRoom = CycleFrame::kMailboxReserve + kDatagramOverhead + kAlStatusReadLength;
constexpr std::uint16_t kOp = static_cast<std::uint16_t>(reg::AlState::op);
constexpr std::uint16_t kSafeOp = static_cast<std::uint16_t>(reg::AlState::safe_op);

}  // namespace

bool ReintegrationService::reintegrate(SlaveMask slaves) noexcept {
  if (slaves == 0 || reintegrating_ != 0 || ctx_.state != MasterState::op || ctx_.options.online_recovery) return false;
  if ((slaves & ~ctx_.monitor.restored()) != 0) return false;
  reintegrating_ = slaves;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) != 0) ctx_.slaves[p].re = ReStep::fmmus;
  }
  re_deadline_ = ctx_.now() + kReintegrationTimeout;
  return true;
}

void ReintegrationService::start_rearm(SlaveMask slaves) noexcept {
  slaves &= ~reintegrating_;
  if (slaves == 0) return;
  if (rearming_ == 0) rearm_deadline_ = ctx_.now() + kReintegrationTimeout;
  rearming_ |= slaves;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) != 0) ctx_.slaves[p].re = ReStep::acknowledge;
  }
}

void ReintegrationService::add_datagrams(CycleFrame& frame) noexcept {
  if (ctx_.state != MasterState::op) return;
  rearming_ &= ctx_.monitor.in_exchange();  // one the probes took out is the monitor's (and recovery's) now
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if (((reintegrating_ | rearming_) & slave_bit(p)) == 0) continue;
    if ((rearming_ & slave_bit(p)) != 0 && frame.remaining() < kRearmRoom) continue;
    const std::uint16_t station = ctx_.plan[p].station_address;
    const auto tag = static_cast<std::uint8_t>(p);
    std::array<std::uint8_t, std::size_t{2} * reg::kFmmuSize> bytes{};
    const ReStep step = ctx_.slaves[p].re;
    switch (step) {
      case ReStep::fmmus:
        fill_fmmus(ctx_.slaves[p].setup, ctx_.plan[p], ctx_.layout.slaves[p], bytes.data());
        (void)frame.add(*this, tag, Command::FPWR, make_address(station, reg::fmmu(kFmmuOutputs)), 2 * reg::kFmmuSize,
                        ConstByteSpan(bytes));
        break;
      case ReStep::status:
        (void)frame.add(*this, tag, Command::FPRD, make_address(station, reg::kAlStatus), kAlStatusReadLength);
        break;
      case ReStep::acknowledge:
      case ReStep::request_op:
        store_le16(bytes.data(), step == ReStep::acknowledge ? static_cast<std::uint16_t>(kSafeOp | reg::kAlErrorBit) : kOp);
        (void)frame.add(*this, tag, Command::FPWR, make_address(station, reg::kAlControl), 2, ConstByteSpan(bytes.data(), 2));
        break;
    }
  }
}

void ReintegrationService::on_answer(std::uint8_t p, const DatagramView& d) noexcept {
  if (((reintegrating_ | rearming_) & slave_bit(p)) == 0 || d.wkc() != 1) return;  // no answer: same step again
  const hal::Nanoseconds now = ctx_.now();
  const bool rearm = (rearming_ & slave_bit(p)) != 0;
  SlaveRecord& slave = ctx_.slaves[p];
  if (slave.re != ReStep::status) {
    slave.re = ReStep::status;
    return;
  }
  const std::uint8_t* data = d.data().data();
  const std::uint16_t status = load_le16(data);
  slave.note_al_status(data);
  const std::uint16_t al_state = status & reg::kAlStateMask;
  if ((status & reg::kAlErrorBit) == 0 && al_state == kOp && rearm) {
    rearming_ &= ~slave_bit(p);
    ctx_.monitor.rearmed(slave_bit(p), ctx_.cycle, now);
  } else if ((status & reg::kAlErrorBit) == 0 && al_state == kOp) {
    reintegrating_ &= ~slave_bit(p);
    ctx_.monitor.reintegrated(slave_bit(p), ctx_.cycle, now);
  } else if ((status & reg::kAlErrorBit) != 0) {
    slave.re = ReStep::acknowledge;
  } else if (al_state == kSafeOp) {
    slave.re = ReStep::request_op;
  } else if (rearm) {
    rearming_ &= ~slave_bit(p);
    ctx_.monitor.rearm_failed(slave_bit(p), ctx_.cycle, now, status, load_le16(data + 4));
  } else {
    reintegrating_ &= ~slave_bit(p);
    ctx_.monitor.reintegration_failed(slave_bit(p), ctx_.cycle, now, status, load_le16(data + 4));
  }
}

void ReintegrationService::settle(CycleResult& /*result*/) noexcept {
  if (ctx_.state != MasterState::op) return;
  start_rearm(ctx_.monitor.take_rearm_requests());
  if (rearming_ != 0 && ctx_.now() > rearm_deadline_) {
    ctx_.monitor.rearm_failed(rearming_, ctx_.cycle, ctx_.now(), 0, 0);
    rearming_ = 0;
  }
  if (reintegrating_ == 0 || ctx_.now() <= re_deadline_) return;
  ctx_.monitor.reintegration_failed(reintegrating_, ctx_.cycle, ctx_.now(), 0, 0);
  reintegrating_ = 0;
}

}  // namespace rescue::ecat
