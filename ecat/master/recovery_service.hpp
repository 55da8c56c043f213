// Online recovery in the cycle (OP only, MasterOptions::online_recovery): an operated slave out of
// the exchange is searched for at its position and, when it answers, configured again and brought
// back to OP while the others cycle. Each slave's progress is its SlaveRecord's `recovery`, driven
// by the slave_recovery table (slave_recovery.hpp); this service does what each state says, at most
// MasterOptions::recovery_datagrams_per_cycle datagrams per cycle in all (recovery_service.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include "ecat/mailbox/mailbox_client.hpp"
#include "ecat/master/cyclic_service.hpp"
#include "ecat/master/dc_reference_service.hpp"
#include "ecat/master/pdo_setup_service.hpp"
#include "ecat/master/reintegration_service.hpp"

namespace rescue::ecat {

// Online recovery's counters (for tests, benches and the docs' figures).
struct RecoveryStats {
  std::uint64_t datagrams{0};            // recovery datagrams sent in all
  std::uint32_t max_datagrams_per_cycle{0};
  std::uint32_t recovered{0};
  std::uint32_t refused{0};
  std::uint32_t failed{0};
  std::uint64_t table_refusals{0};       // (state, input) pairs without a row (a bug if ever non-zero)
  std::uint32_t shared_addresses{0};     // station addresses found on two devices at once, withdrawn
};

class RecoveryService final : public CyclicService {
 public:
  RecoveryService(ServiceContext& context, const DcReferenceService& dc, const ReintegrationService& reintegration,
                  PdoSetupService& sdos, MailboxClient& mailbox) noexcept
      : ctx_(context), dc_(dc), reintegration_(reintegration), sdos_(sdos), mailbox_(mailbox) {}

  SlaveMask recovering() const noexcept;
  const RecoveryStats& stats() const noexcept { return stats_; }
  // Bring-up: every slave idle, the counters zero.
  void reset() noexcept { stats_ = RecoveryStats{}; }

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override;

 private:
  bool add_step(CycleFrame& frame, std::size_t position) noexcept;
  bool add_search(CycleFrame& frame) noexcept;
  void on_step_answer(std::size_t position, const DatagramView& datagram) noexcept;
  void on_search_answer(std::size_t position, const DatagramView& datagram) noexcept;
  // Its station address answered by more than one device: withdrawn from all (searched for again).
  void separate_devices(std::size_t position) noexcept;
  // The slave_recovery machine's input; its actions (RecoveryActions) act on this service.
  void take_input(std::size_t position, RecoveryInput input) noexcept;
  friend struct RecoveryActions;
  void check_identity(std::size_t position) noexcept;
  // The slave being searched for whose bring-up identity is this device's (kMaxSlaves: none).
  std::size_t owner_of_identity(std::size_t finder) const noexcept;
  // Whether a slave other than `except` is about to write its station address at that place.
  bool addressing_at(std::uint16_t adp, std::size_t except) const noexcept;
  hal::Nanoseconds hold_off(std::uint8_t failures) const noexcept;
  // The auto-increment places the slave may be at: `first` slaves before it surely answer, up to
  // `unknown` more may (searched for, or waiting after a failure).
  struct Places {
    std::uint16_t first{0};
    std::uint16_t unknown{0};
  };
  Places expected_places(std::size_t position) const noexcept;
  // The DC slave in the exchange nearest after the reference clock: its clock stands in for the
  // network's time while the reference, restarted, is set again (kMaxSlaves: none).
  std::size_t clock_stand_in() const noexcept;

  ServiceContext& ctx_;
  const DcReferenceService& dc_;
  const ReintegrationService& reintegration_;
  PdoSetupService& sdos_;
  MailboxClient& mailbox_;
  RecoveryStats stats_{};
  std::size_t rotate_{0};
  std::size_t search_rotate_{0};
  std::uint32_t datagrams_this_cycle_{0};
};

}  // namespace rescue::ecat
