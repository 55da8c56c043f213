#include "ecat/master/link_diagnostics.hpp"

#include "ecat/codec/registers.hpp"
#include "ecat/master/network_match.hpp"

namespace rescue::ecat {

std::uint8_t cable_peer(const NetworkPlan& plan, std::size_t position, unsigned port) noexcept {
  if (position >= kMaxSlaves || port >= kEscPorts) return kNoPosition;
  if (port == 0) return plan[position].upstream == kMasterUpstream ? kMasterEnd : plan[position].upstream;
  for (std::size_t q = 0; q < kMaxSlaves; ++q) {
    if (plan[q].upstream == position && plan[q].upstream_port == port) return static_cast<std::uint8_t>(q);
  }
  return kNoPosition;
}

void LinkDiagnostics::reset() noexcept {
  counters_.fill(SlaveErrorCounters{});
  for (auto& s : score_) s.fill(0);
  for (auto& w : warned_) w.fill(false);
  ever_warned_.fill(0);
  rotate_ = 0;
  sweeps_ = 0;
  PortErrorWarning drop;
  while (warnings_.pop(drop)) {
  }
}

void LinkDiagnostics::reset_slaves(SlaveMask slaves) noexcept {
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) == 0) continue;
    counters_[p] = SlaveErrorCounters{};
    score_[p].fill(0);
    warned_[p].fill(false);
    ever_warned_[p] = 0;
  }
  ++resets_;
}

std::size_t LinkDiagnostics::next(SlaveMask candidates) noexcept {
  for (std::size_t i = 0; i < kMaxSlaves; ++i) {
    const std::size_t p = (rotate_ + i) % kMaxSlaves;
    if ((candidates & slave_bit(p)) == 0) continue;
    if (p < rotate_) ++sweeps_;  // wrapped around: the previous sweep is complete
    rotate_ = p + 1;
    return p;
  }
  return kMaxSlaves;
}

void LinkDiagnostics::observe(std::size_t p, const std::uint8_t* data, std::uint64_t cycle, hal::Nanoseconds time) noexcept {
  if (p >= kMaxSlaves || data == nullptr) return;
  SlaveErrorCounters& c = counters_[p];
  ++c.reads;
  for (unsigned n = 0; n < kEscPorts; ++n) {
    PortCounters& port = c.ports[n];
    const std::size_t pair = std::size_t{2} * n;  // 0x0300 + 2n: invalid frames, then RX errors
    const std::uint32_t invalid = data[pair];
    const std::uint32_t rx = data[pair + 1];
    port.invalid_frames += invalid;
    port.rx_errors += rx;
    port.forwarded_errors += data[reg::kForwardedRxErrorCounter - reg::kRxErrorCounter + n];
    port.lost_links += data[reg::kLostLinkCounter - reg::kRxErrorCounter + n];
    std::uint32_t& score = score_[p][n];
    score = score - score / 8 + kScorePerError * (invalid + rx);
    if (!warned_[p][n] && score >= kWarnScore) {
      warned_[p][n] = true;
      ever_warned_[p] = static_cast<std::uint8_t>(ever_warned_[p] | (1U << n));
      PortErrorWarning w;
      w.slave = static_cast<std::uint8_t>(p);
      w.port = static_cast<std::uint8_t>(n);
      w.peer = cable_peer(plan_, p, n);
      w.errors = port.invalid_frames + port.rx_errors;
      w.cycle = cycle;
      w.time = time;
      if (!warnings_.push(w)) ++warnings_dropped_;
    } else if (warned_[p][n] && score < kWarnScore / 2) {
      warned_[p][n] = false;
    }
  }
  c.processing_unit_errors += data[reg::kEpuErrorCounter - reg::kRxErrorCounter];
  c.pdi_errors += data[reg::kPdiErrorCounter - reg::kRxErrorCounter];
}

void LinkDiagnostics::print_table(std::FILE* out, SlaveMask slaves, const char* (*name)(std::size_t)) const noexcept {
  std::fprintf(out, "%-3s %-18s", "pos", "slave");
  for (unsigned n = 0; n < kEscPorts; ++n) std::fprintf(out, " | port %u inv/rx/fwd/lost", n);
  std::fprintf(out, " | epu | pdi | reads\n");
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) == 0) continue;
    const SlaveErrorCounters& c = counters_[p];
    std::fprintf(out, "%-3zu %-18s", p, name != nullptr ? name(p) : plan_[p].name);
    for (const PortCounters& port : c.ports) {
      std::fprintf(out, " | %5u/%4u/%4u/%4u   ", static_cast<unsigned>(port.invalid_frames), static_cast<unsigned>(port.rx_errors),
                   static_cast<unsigned>(port.forwarded_errors), static_cast<unsigned>(port.lost_links));
    }
    std::fprintf(out, " | %3u | %3u | %u\n", static_cast<unsigned>(c.processing_unit_errors), static_cast<unsigned>(c.pdi_errors),
                 static_cast<unsigned>(c.reads));
  }
}

}  // namespace rescue::ecat
