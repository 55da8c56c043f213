// A slave's configuration as its SII gives it (SyncManagers, mailbox, complete access), and the
// register blocks the master writes from it (bring-up, re-integration, online recovery alike).
#pragma once

#include <array>
#include <cstdint>

#include "ecat/link/network_plan.hpp"

namespace rescue::ecat {

// What one SyncManager of a slave looks like, from its SII.
struct SyncManagerSetup {
  std::uint16_t start{0};
  std::uint16_t length{0};
  std::uint8_t control{0};
  bool present{false};
};

struct SlaveSetup {
  std::array<SyncManagerSetup, 4> sm{};  // 0 mailbox out, 1 mailbox in, 2 outputs, 3 inputs
  bool mailbox{false};                   // standard mailbox present, CoE supported
  bool complete_access{false};           // SII general: SDO complete access supported
};

// SM0/SM1 (mailbox), 2 x 8 bytes, into `out`.
void fill_mailbox_sms(const SlaveSetup& setup, std::uint8_t* out) noexcept;
// SM2/SM3 (process data, sized by the plan), 2 x 8 bytes, into `out`.
void fill_process_data_sms(const SlaveSetup& setup, const SlavePlan& plan, std::uint8_t* out) noexcept;
// FMMU0 (outputs) / FMMU1 (inputs) onto the process image, 2 x 16 bytes, into `out`.
void fill_fmmus(const SlaveSetup& setup, const SlavePlan& plan, const SlaveImage& image, std::uint8_t* out) noexcept;

}  // namespace rescue::ecat
