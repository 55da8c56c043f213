// The mailbox client's datagrams in the cycle frame.
#include "ecat/master/mailbox_service.hpp"

#include "ecat/link/master_capacities.hpp"

namespace rescue::ecat {

void MailboxService::add_datagrams(CycleFrame& frame) noexcept {
  const std::size_t added = client_.add_datagrams(frame.builder(), frame.index(), ctx_.now(), kCyclicMailboxSlaves);
  for (std::size_t k = 0; k < added; ++k) frame.note(*this, static_cast<std::uint8_t>(k));
}

}  // namespace rescue::ecat
