// The cycle frame's handles: which service answers which datagram.
#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

bool CycleFrame::add(CyclicService& by, std::uint8_t tag, Command command, std::uint32_t address, std::uint16_t length,
                     ConstByteSpan data) noexcept {
  if (!builder_->add(command, index_, address, length, data).ok()) return false;
  note(by, tag);
  return true;
}

void CycleFrame::note(CyclicService& by, std::uint8_t tag) noexcept {
  if (count_ < handles_.size()) handles_[count_++] = Handle{&by, tag};
}

void CycleFrame::dispatch(const FrameView& back) const noexcept {
  std::size_t i = 0;
  for (const DatagramView d : back) {
    if (i >= count_) break;
    const Handle& h = handles_[i++];
    h.service->on_answer(h.tag, d);
  }
}

}  // namespace rescue::ecat
