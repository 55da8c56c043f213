// SAFE-OP -> OP in the first cycles (state going_op): per slave not yet in OP, FPWR AL control = OP,
// then FPRD AL status until OP; a refusal (error bit) is acknowledged (SAFE-OP + acknowledge, in a
// frame of its own) and OP written again, up to AlOptions::retries. All in OP: the master is in OP
// and the link monitor starts. After MasterOptions::op_timeout the report names the slave that did
// not follow and every slave not in OP is acknowledged and asked again.
#pragma once

#include <cstdint>

#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

class OpStepService final : public CyclicService {
 public:
  explicit OpStepService(ServiceContext& context) noexcept : ctx_(context) {}

  // Bring-up reached SAFE-OP: every operated slave is to go to OP.
  void start() noexcept;
  SlaveMask pending() const noexcept { return pending_; }

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t position, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override;

 private:
  ServiceContext& ctx_;
  SlaveMask pending_{0};  // slaves not yet confirmed in OP
  hal::Nanoseconds deadline_{0};
};

}  // namespace rescue::ecat
