// Distributed clocks in the cycle: FRMW of the reference clock's system time (0x0910), first in
// every frame. Its answer is the reference time as the frame passed the reference (the master keeps
// its period in step with it: DcCycleSync) and the other DC slaves' clocks are set from it (static
// drift compensation goes on cyclically; online recovery sets a returning slave's offset from it).
// While the reference is out of the exchange (lost, or power-cycled and being recovered) it is read
// by FPRD: its time is not copied into the other clocks until recovery has set it again from theirs.
#pragma once

#include <cstdint>

#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

class DcReferenceService final : public CyclicService {
 public:
  explicit DcReferenceService(ServiceContext& context) noexcept : ctx_(context) {}

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override { result.reference_time = frame_reference_time_; }

  // The ring is open and the reference lies behind the break (ring_dc_service.hpp): only the ring
  // copy reaches it, in which an FRMW goes as NOP, so it is read by FPRD and its time written to the
  // others by the ring-side time writes.
  void set_reference_behind_break(bool behind) noexcept { behind_break_ = behind; }

  // This cycle's reference read (0: none), and the last one read (building a frame: the previous cycle's).
  std::uint64_t frame_reference_time() const noexcept { return frame_reference_time_; }
  std::uint64_t latest_reference_time() const noexcept { return latest_reference_time_; }

 private:
  ServiceContext& ctx_;
  std::uint64_t frame_reference_time_{0};
  std::uint64_t latest_reference_time_{0};
  bool answered_{true};  // the last reference read answered
  bool behind_break_{false};
};

}  // namespace rescue::ecat
