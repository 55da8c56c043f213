// Process data in the cycle: one LRW per branch of the process image (outputs first, inputs after).
// Slaves out of the exchange or not operated get all-zero outputs first (controlword 0: disable
// voltage), so one that answers again before its FMMUs are off receives no motion. The answers'
// inputs are copied into the image; each branch's working counter goes to the cycle's result.
#pragma once

#include <array>
#include <cstdint>

#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

class ProcessDataService final : public CyclicService {
 public:
  explicit ProcessDataService(ServiceContext& context) noexcept : ctx_(context) {}

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t branch, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override { result.branch_wkc = branch_wkc_; }

 private:
  void silence_outputs_of_out_slaves() noexcept;

  ServiceContext& ctx_;
  std::array<std::uint16_t, kMaxBranches> branch_wkc_{};
};

}  // namespace rescue::ecat
