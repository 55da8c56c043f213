// The ESC error counters' reads and clearing writes in the cycle frame.
#include "ecat/master/esc_diagnostics_service.hpp"

#include "ecat/codec/registers.hpp"

namespace rescue::ecat {
namespace {

constexpr std::size_t kDiagnosticsBytes = kDatagramOverhead + LinkDiagnostics::kReadLength;
constexpr std::uint16_t kReadWriteWkc = 3;  // FPRW: read (1) + write (2)
constexpr std::array<std::uint8_t, LinkDiagnostics::kReadLength> kCounterClear{};
// ctl diag --reset: one slave's counters cleared by FPWR, more than this many by one BWR to every slave.
constexpr int kMaxClearWritesPerFrame = 3;

}  // namespace

void EscDiagnosticsService::reset_slaves(SlaveMask slaves) noexcept {
  SlaveMask planned = 0;
  for (std::size_t p = 0; p < ctx_.plan.size() && p < kMaxSlaves; ++p) planned |= slave_bit(p);
  slaves &= planned;
  table_.reset_slaves(slaves);
  clear_pending_ |= slaves;
}

void EscDiagnosticsService::add_clearing_writes(CycleFrame& frame) noexcept {
  // The ESC counters of the reset slaves are cleared by writing them (ET1100 datasheet: a write to
  // any of 0x0300-0x030B clears those twelve, to 0x0310-0x0313 the lost-link counters, to 0x030C /
  // 0x030D that counter), ahead of the round robin's read in the same frame.
  clear_pending_ |= clear_in_flight_;  // the last frame's writes were not all answered
  clear_in_flight_ = 0;
  if (popcount(clear_pending_) > kMaxClearWritesPerFrame) {
    if (frame.fits(kDiagnosticsBytes)) {
      (void)frame.add(*this, kBroadcastTag, Command::BWR, make_address(0, reg::kRxErrorCounter), LinkDiagnostics::kReadLength,
                      ConstByteSpan(kCounterClear));
      clear_in_flight_ = clear_pending_;
      clear_pending_ = 0;
    }
    return;
  }
  for (std::size_t p = 0; p < kMaxSlaves && clear_pending_ != 0; ++p) {
    if ((clear_pending_ & slave_bit(p)) == 0 || !frame.fits(kDiagnosticsBytes)) continue;
    (void)frame.add(*this, static_cast<std::uint8_t>(p), Command::FPWR,
                    make_address(ctx_.plan[p].station_address, reg::kRxErrorCounter), LinkDiagnostics::kReadLength,
                    ConstByteSpan(kCounterClear));
    clear_in_flight_ |= slave_bit(p);
    clear_pending_ &= ~slave_bit(p);
  }
}

void EscDiagnosticsService::add_datagrams(CycleFrame& frame) noexcept {
  if (ctx_.state != MasterState::op) return;
  add_clearing_writes(frame);
  const unsigned interval = ctx_.options.diag_interval_cycles;
  if (interval == 0 || ctx_.cycle % interval != 0 || !frame.fits(kDiagnosticsBytes)) return;
  const std::size_t p = table_.next(ctx_.monitor.in_exchange());
  if (p >= kMaxSlaves) return;
  (void)frame.add(*this, static_cast<std::uint8_t>(p | kReadTag), Command::FPRW,
                  make_address(ctx_.plan[p].station_address, reg::kRxErrorCounter), LinkDiagnostics::kReadLength,
                  ConstByteSpan(kCounterClear));
}

void EscDiagnosticsService::on_answer(std::uint8_t tag, const DatagramView& d) noexcept {
  if ((tag & kReadTag) != 0) {
    const std::size_t p = tag & static_cast<std::uint8_t>(~kReadTag);
    // A slave reset but not yet cleared in its ESC: its answer holds errors from before the reset.
    if (d.wkc() == kReadWriteWkc && (clear_pending_ & slave_bit(p)) == 0) {
      table_.observe(p, d.data().data(), ctx_.cycle, ctx_.now());
    }
    return;
  }
  // Written: done. Not answered (a lost slave, a cut): written again next frame, unless the slave
  // is out of the exchange (it is cleared when it is read again after its recovery).
  if (tag == kBroadcastTag) {
    if (d.wkc() != 0) clear_in_flight_ = 0;
  } else if (d.wkc() != 0 || (ctx_.monitor.in_exchange() & slave_bit(tag)) == 0) {
    clear_in_flight_ &= ~slave_bit(tag);
  }
}

void EscDiagnosticsService::settle(CycleResult& /*result*/) noexcept {
  if (ctx_.state != MasterState::op) return;
  PortErrorWarning warning;
  while (table_.pop_warning(warning)) {
    ctx_.monitor.recovery_event(LinkEventKind::port_errors, slave_bit(warning.slave), ctx_.cycle, warning.time,
                                {warning.port, warning.peer, warning.errors, 0});
  }
}

}  // namespace rescue::ecat
