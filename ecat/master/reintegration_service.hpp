// Re-integration of restored slaves while cycling (OP only; an explicit action of the master's
// owner, Master::reintegrate). A slave whose link came back kept its configuration (station
// address, SyncManagers, DC offset and delay, SYNC0), except the FMMUs the master switched off when
// it was lost; its process-data watchdog has usually taken it to SAFE-OP with an error (0x001B).
// So, one datagram per cycle and slave:
//   fmmus        FPWR 0x0600: FMMU0 (outputs) and FMMU1 (inputs) as at bring-up
//   status       FPRD 0x0130: OP -> done; error -> acknowledge; SAFE-OP -> request OP;
//                below SAFE-OP -> failed (needs a bring-up: its SMs/DC may be gone)
//   acknowledge  FPWR 0x0120 = SAFE-OP + error acknowledge, then status again
//   request_op   FPWR 0x0120 = OP, then status again
// Its outputs stay all-zero until it is back in the exchange (process_data_service.hpp).
//
// Re-arming uses the same steps from `acknowledge`: a slave the watchdog check found in SAFE-OP by
// its watchdog after the master's silence (link_monitor.hpp, item 5). It kept its FMMUs and stays
// in the exchange meanwhile; its datagrams leave room for a mailbox step like the probes.
#pragma once

#include <cstdint>

#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

class ReintegrationService final : public CyclicService {
 public:
  explicit ReintegrationService(ServiceContext& context) noexcept : ctx_(context) {}

  // See Master::reintegrate.
  [[nodiscard]] bool reintegrate(SlaveMask slaves) noexcept;
  SlaveMask reintegrating() const noexcept { return reintegrating_; }
  // Bring-up: no re-integration carries over.
  void reset() noexcept { reintegrating_ = 0; }

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t position, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override;

 private:
  // Re-arming slaves the watchdog check found in SAFE-OP by their watchdog (same steps, from the
  // acknowledge; they stay in the exchange meanwhile).
  void start_rearm(SlaveMask slaves) noexcept;

  ServiceContext& ctx_;
  SlaveMask reintegrating_{0};
  SlaveMask rearming_{0};
  hal::Nanoseconds re_deadline_{0};
  hal::Nanoseconds rearm_deadline_{0};
};

}  // namespace rescue::ecat
