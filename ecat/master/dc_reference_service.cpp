// The reference clock's FRMW in every cycle frame.
#include "ecat/master/dc_reference_service.hpp"

#include "core/base/endian.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::ecat {

void DcReferenceService::add_datagrams(CycleFrame& frame) noexcept {
  frame_reference_time_ = 0;
  // Capacity was checked at bring-up (the reference read and every branch always fit). A reference out
  // of the exchange (power-cycled: its time began again) is only read, not copied into the other
  // clocks, until online recovery has set its clock again (their clocks run on meanwhile).
  const Command command = ctx_.reference_out() || !answered_ || behind_break_ ? Command::FPRD : Command::FRMW;
  (void)frame.add(*this, 0, command, make_address(ctx_.reference_station, reg::kDcSystemTime), 8);
}

void DcReferenceService::on_answer(std::uint8_t /*tag*/, const DatagramView& d) noexcept {
  answered_ = d.wkc() != 0;
  frame_reference_time_ = answered_ ? load_le64(d.data().data()) : 0;
  if (frame_reference_time_ != 0) latest_reference_time_ = frame_reference_time_;
}

}  // namespace rescue::ecat
