// ESC error counters in the cycle (OP only; link_diagnostics.hpp): one FPRW of 0x0300..0x0313 to
// one slave in the exchange every MasterOptions::diag_interval_cycles periods (round robin; the
// read returns the counters, the write clears them), and the clearing writes `ctl diag --reset`
// asks for (FPWR per slave, or one BWR when more than kMaxClearWritesPerFrame wait), sent again
// until answered. A rising port becomes a `port_errors` link report naming the cable.
#pragma once

#include <cstdint>

#include "ecat/master/cyclic_service.hpp"
#include "ecat/master/link_diagnostics.hpp"

namespace rescue::ecat {

class EscDiagnosticsService final : public CyclicService {
 public:
  explicit EscDiagnosticsService(ServiceContext& context) noexcept : ctx_(context), table_(context.plan) {}

  const LinkDiagnostics& table() const noexcept { return table_; }
  // Bring-up: nothing of an earlier one carries over.
  void reset() noexcept { table_.reset(); }
  // Master::reset_diagnostics: zeroes the table of `slaves` now; their ESC counters are cleared by
  // datagrams of the next frames.
  void reset_slaves(SlaveMask slaves) noexcept;
  SlaveMask clear_pending() const noexcept { return clear_pending_ | clear_in_flight_; }

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override;

 private:
  static constexpr std::uint8_t kReadTag = 0x80;        // tag bit: the round robin's read (else a clearing write)
  static constexpr std::uint8_t kBroadcastTag = kMaxSlaves;  // the clearing BWR to every slave

  void add_clearing_writes(CycleFrame& frame) noexcept;

  ServiceContext& ctx_;
  LinkDiagnostics table_;
  // Slaves whose ESC counters wait for their clearing write, and those written in the frame under
  // way (back to pending when it is lost or a write is not answered).
  SlaveMask clear_pending_{0};
  SlaveMask clear_in_flight_{0};
};

}  // namespace rescue::ecat
