// The ring watch's datagrams in the cycle frame.
#include "ecat/master/ring_service.hpp"

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kDlStatusLength = 2;

}  // namespace

void RingService::start() noexcept {
  if (!ctx_.link.redundant()) {
    monitor_.stop();
    return;
  }
  std::array<std::uint8_t, kMaxSlaves> planned{};
  planned.fill(RingMonitor::kNoSlavePosition);
  const std::size_t found = ctx_.report.found.size();
  for (std::size_t i = 0; i < found && i < kMaxSlaves; ++i) {
    const std::uint8_t slot = ctx_.report.match.slot_of_found[i];
    planned[i] = slot < kMaxSlaves ? slot : RingMonitor::kNoSlavePosition;
  }
  monitor_.start(planned, found);
}

void RingService::add_datagrams(CycleFrame& frame) noexcept {
  brd_added_ = false;
  if (!ctx_.link.redundant() || monitor_.status().state == RingState::none) return;
  brd_at_ = frame.builder().datagram_count();
  brd_added_ = frame.add(*this, kBrdTag, Command::BRD, make_address(0, reg::kDlStatus), kDlStatusLength);
  const RingStatus& status = monitor_.status();
  if (status.state == RingState::closed) return;
  if (status.before < kMaxSlaves && frame.fits(kDatagramOverhead + kDlStatusLength)) {
    (void)frame.add(*this, kBeforeTag, Command::FPRD, make_address(ctx_.plan[status.before].station_address, reg::kDlStatus),
                    kDlStatusLength);
  }
  if (status.after < kMaxSlaves && frame.fits(kDatagramOverhead + kDlStatusLength)) {
    (void)frame.add(*this, kAfterTag, Command::FPRD, make_address(ctx_.plan[status.after].station_address, reg::kDlStatus),
                    kDlStatusLength);
  }
}

void RingService::on_answer(std::uint8_t tag, const DatagramView& d) noexcept {
  if (tag == kBrdTag || d.length() < kDlStatusLength) return;
  const RingStatus& status = monitor_.status();
  monitor_.observe_dl_status(tag == kBeforeTag ? status.before : status.after, d.wkc(), load_le16(d.data().data()));
}

void RingService::settle(CycleResult& result) noexcept {
  if (!brd_added_ || !result.frame_received) return;
  const CopyReturns& returns = ctx_.link.copy_returns();
  if (brd_at_ >= returns.counters.datagrams) return;
  monitor_.observe(ctx_.cycle, result.sent_at, returns, returns.counters.main[brd_at_], returns.counters.ring[brd_at_]);
}

}  // namespace rescue::ecat
