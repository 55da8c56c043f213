// The ring watch in the cycle (cable redundancy only: without a ring NIC it adds nothing, so a
// single-port frame is byte for byte what it was). Each cycle: a BRD of the DL status (0x0110) whose
// working counter in each returned copy says how far each port reaches (ring_monitor.hpp), and while
// the ring is not closed an FPRD of the DL status of the two slaves beside the break (port link and
// loop bits: which port lost its link). After the exchange the ring monitor decides the state.
#pragma once

#include <cstdint>

#include "ecat/master/cyclic_service.hpp"
#include "ecat/master/ring_monitor.hpp"

namespace rescue::ecat {

class RingService final : public CyclicService {
 public:
  explicit RingService(ServiceContext& context) noexcept : ctx_(context) {}

  // From the bring-up's match: the segment's slaves in processing order, as planned positions.
  void start() noexcept;
  void stop() noexcept { monitor_.stop(); }

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override;

  const RingMonitor& monitor() const noexcept { return monitor_; }
  [[nodiscard]] bool pop_report(RingReport& out) noexcept { return monitor_.pop_report(out); }

 private:
  static constexpr std::uint8_t kBrdTag = 0;
  static constexpr std::uint8_t kBeforeTag = 1;
  static constexpr std::uint8_t kAfterTag = 2;

  ServiceContext& ctx_;
  RingMonitor monitor_{};
  std::size_t brd_at_{0};  // the BRD's place in this cycle's frame
  bool brd_added_{false};
};

}  // namespace rescue::ecat
