// The link monitor's probes in the cycle frame.
#include "ecat/master/link_probe_service.hpp"

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/master/slave_config.hpp"

namespace rescue::ecat {
namespace {

constexpr std::size_t kProbeBytes = 2 * kDatagramOverhead + kAlStatusReadLength + kFmmuActivationOffLength;
constexpr std::array<std::uint8_t, kFmmuActivationOffLength> kZeros{};

}  // namespace

void LinkProbeService::add_datagrams(CycleFrame& frame) noexcept {
  count_ = 0;
  if (ctx_.state != MasterState::op) return;
  const std::size_t planned = ctx_.monitor.plan_probes(probes_.data(), probes_.size());
  std::size_t kept = 0;
  for (std::size_t i = 0; i < planned && frame.fits(kProbeBytes); ++i, ++kept) {
    const ProbeRequest& probe = probes_[i];
    const std::uint16_t station = ctx_.plan[probe.position].station_address;
    const auto tag = static_cast<std::uint8_t>(i);
    results_[i] = ProbeResult{probe.position, probe.clear_fmmus, probe.watch, 0, 0, 0, 0, false};
    (void)frame.add(*this, tag, Command::FPRD, make_address(station, reg::kAlStatus), kAlStatusReadLength);
    if (probe.clear_fmmus) {
      (void)frame.add(*this, static_cast<std::uint8_t>(tag | kClearTag), Command::FPWR,
                      make_address(station, kFmmuActivationOffAddress), kFmmuActivationOffLength, ConstByteSpan(kZeros));
    }
  }
  count_ = kept;  // the rest are asked for again next cycle
}

void LinkProbeService::on_answer(std::uint8_t tag, const DatagramView& d) noexcept {
  ProbeResult& r = results_[tag & static_cast<std::uint8_t>(~kClearTag)];
  if ((tag & kClearTag) != 0) {
    r.clear_wkc = d.wkc();
    return;
  }
  if (answer_lost_with_a_copy(ctx_.link.copy_returns(), d)) {
    r.no_evidence = true;  // the slave may have answered in the copy lost
    return;
  }
  const std::uint8_t* data = d.data().data();
  r.status_wkc = d.wkc();
  r.al_status = load_le16(data);
  r.al_status_code = load_le16(data + 4);
  if (d.wkc() == 1 && r.position < kMaxSlaves) ctx_.slaves[r.position].note_al_status(data);
}

void LinkProbeService::settle(CycleResult& result) noexcept {
  if (ctx_.state != MasterState::op) return;
  ctx_.monitor.observe(ctx_.cycle, result.sent_at, result.frame_received, result.branch_wkc,
                       Span<const ProbeResult>(results_.data(), count_));
  result.valid = ctx_.monitor.valid();
}

}  // namespace rescue::ecat
