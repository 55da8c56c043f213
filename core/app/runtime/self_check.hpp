// `rescue-motion run --check` (docs/deploy.md): brings the EtherCAT network up to OP, exchanges
// frames for a short while with every output zero (controlword 0: no drive is ever enabled), sends
// every slave back to INIT, and prints one line saying what it saw; a failed bring-up's line is
// followed by the rest of its report (ecat/master/bring_up_report.hpp: the network's differences from
// the plan, the slave that refused a state and its AL status code, a refused SDO, the link's counters). Exit status 0 when the network
// reached OP, no drive reported Operation enabled, and every slave answered INIT; 1 otherwise. A raw
// interface is locked first (hal/files/instance_lock.hpp): a running service keeps it, and the check refuses.
#pragma once

#include <cstdint>
#include <cstdio>

#include "core/app/config/nic_option.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

struct SelfCheckOptions {
  NicChoice nic{};
  const char* nic_text{"sim"};
  // --ring-nic: the second master port (cable redundancy); nullptr text: none.
  NicChoice ring_nic{};
  const char* ring_nic_text{nullptr};
  hal::Nanoseconds op_timeout{5 * hal::kNsPerSec};      // from SAFE-OP to OP
  hal::Nanoseconds hold_in_op{200 * hal::kNsPerMs};     // frames exchanged in OP before going back
  const char* capture_path{nullptr};  // every frame of the check recorded there (pcapng), when given
  // One line per phase (bringing the network up, SAFE-OP, OP, back to INIT), each flushed at once so
  // a pipe sees it while the check runs; nullptr: none. `run --check` gives stderr: stdout keeps its
  // one verdict line for scripts.
  std::FILE* progress{nullptr};
};

struct SelfCheckReport {
  bool reached_op{false};
  bool back_in_init{false};
  bool drive_enabled{false};  // a drive reported Operation enabled (must never happen)
  unsigned slaves{0};
  std::uint64_t cycles_in_op{0};
  std::uint64_t frames_missing{0};
  double op_after_s{0.0};
};

// Writes its one verdict line to `out` (the phases to options.progress); fills `report` when not nullptr. Returns the exit status.
int run_self_check(const SelfCheckOptions& options, std::FILE* out, SelfCheckReport* report) noexcept;

}  // namespace rescue::app
