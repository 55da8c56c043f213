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
  // On the ring, a datagram whose answer may have been lost with a copy goes unanswered: the client
  // then asks for the lost answer again or rewrites the request, as for a lost frame.
  void on_answer(std::uint8_t k, const DatagramView& datagram) noexcept override {
    if (!answer_lost_with_a_copy(ctx_.link.copy_returns(), datagram)) client_.on_datagram(k, datagram);
  }
  void end_exchange(hal::Nanoseconds now) noexcept override { client_.end_exchange(now); }

 private:
  ServiceContext& ctx_;
  MailboxClient& client_;
};

}  // namespace rescue::ecat
