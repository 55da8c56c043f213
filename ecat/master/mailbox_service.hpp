// Aperiodic CoE SDO transfers in the cycle: the mailbox client's step (one datagram pair per busy
// slave, of at most kCyclicMailboxSlaves slaves) goes last into every frame, in the room the other
// optional datagrams leave it (CycleFrame::kMailboxReserve).
#pragma once

#include <cstdint>

#include "ecat/mailbox/mailbox_client.hpp"
#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

class MailboxService final : public CyclicService {
 public:
  MailboxService(ServiceContext& context, MailboxClient& client) noexcept : ctx_(context), client_(client) {}

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t k, const DatagramView& datagram) noexcept override { client_.on_datagram(k, datagram); }
  void end_exchange(hal::Nanoseconds now) noexcept override { client_.end_exchange(now); }

 private:
  ServiceContext& ctx_;
  MailboxClient& client_;
};

}  // namespace rescue::ecat
