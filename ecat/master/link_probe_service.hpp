// Link probes and the AL-state watch in the cycle (OP only): the link monitor (link_monitor.hpp, the
// one loss decider) plans which slaves to probe this cycle (suspects, slaves out of the exchange,
// watchdog checks, the watch's round robin over the slaves in the exchange); each probe is an FPRD of
// the AL status, plus an FPWR switching the FMMUs off for a slave out of the exchange. After the
// exchange the monitor observes the branches' working counters and the probes' answers and decides
// which slaves are valid, lost, restored or not operational.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

class LinkProbeService final : public CyclicService {
 public:
  explicit LinkProbeService(ServiceContext& context) noexcept : ctx_(context) {}

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override;

 private:
  static constexpr std::uint8_t kClearTag = 0x80;  // tag bit: the probe's FMMU write (else its AL status read)

  ServiceContext& ctx_;
  std::array<ProbeRequest, kMaxSlaves> probes_{};
  std::array<ProbeResult, kMaxSlaves> results_{};
  std::size_t count_{0};
};

}  // namespace rescue::ecat
