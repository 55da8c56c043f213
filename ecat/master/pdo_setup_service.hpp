// PDO set-up and start-up SDOs of slaves under online recovery (recovery_service.hpp, state
// StartupSdos): each such slave's PDO mapping (pdo_setup.hpp: read, what differs written, read
// back), then the owner's start-up SDOs for it (MasterOptions::startup_sdos), through the cyclic
// mailbox channel (mailbox_service.hpp), one transfer per slave in the queue at a time so several
// slaves recovering at once never overflow it. It adds no datagrams of its own: after each exchange
// it takes the master's completions from the mailbox client and feeds the next transfers in.
#pragma once

#include <cstddef>
#include <cstdint>

#include "ecat/mailbox/mailbox_client.hpp"
#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

class PdoSetupService final : public CyclicService {
 public:
  PdoSetupService(ServiceContext& context, MailboxClient& mailbox) noexcept : ctx_(context), mailbox_(mailbox) {}

  // The slave entered StartupSdos: its mapping first, then its start-up SDOs.
  void start(std::size_t position) noexcept;
  // Submits the slave's next transfer when it has none queued and the queue has room.
  void feed(std::size_t position) noexcept;
  // Every transfer of the slave done and none refused.
  bool done(std::size_t position) const noexcept;

  void add_datagrams(CycleFrame& /*frame*/) noexcept override {}
  void on_answer(std::uint8_t /*tag*/, const DatagramView& /*datagram*/) noexcept override {}
  void settle(CycleResult& result) noexcept override;

 private:
  ServiceContext& ctx_;
  MailboxClient& mailbox_;
  std::size_t rotate_{0};
};

}  // namespace rescue::ecat
