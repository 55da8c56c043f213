// What the master tells its owner: the bring-up's report (which step failed and why, where the time
// went) and each cycle's result. Filled by the master and its cyclic services (cyclic_service.hpp).
#pragma once

#include <array>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/containers/fixed_vector.hpp"
#include "ecat/dc/dc_delay.hpp"
#include "ecat/link/network_plan.hpp"
#include "ecat/mailbox/mailbox_client.hpp"
#include "ecat/master/al_control.hpp"
#include "ecat/master/master_options.hpp"
#include "ecat/master/network_match.hpp"
#include "ecat/sii/sii_reader.hpp"
#include "hal/time/clock.hpp"

namespace rescue::ecat {

// Where bring-up time goes: when each step began and how many frames had been exchanged by then.
struct BringUpStepMark {
  const char* step{nullptr};
  hal::Nanoseconds at{0};
  std::uint64_t frames{0};
};
constexpr std::size_t kBringUpSteps = 12;

struct BringUpReport {
  const char* failed_step{nullptr};  // nullptr when bring-up succeeded
  std::array<BringUpStepMark, kBringUpSteps> steps{};  // in order; steps[step_count - 1] is the last begun
  std::uint8_t step_count{0};
  Error error{};
  std::uint16_t slaves_counted{0};
  std::uint32_t first_contact_frames{0};  // count BRDs sent until one came back
  FixedVector<FoundSlave, kMaxFoundSlaves> found{};
  NetworkMatch match{};
  AlFailure al_failure{};
  SiiReadStats sii{};
  SdoCompletion failed_sdo{};            // when the failed step is "PRE-OP SDO"
  std::uint32_t startup_sdos_done{0};
  // PDO mapping set-up (pdo_setup.hpp): transfers in all, and the slaves whose mapping was rewritten.
  std::uint32_t pdo_reads{0};
  std::uint32_t pdo_writes{0};
  SlaveMask pdo_rewritten{0};
  DcDelays delays{};
  std::uint32_t dc_max_difference_ns{0};  // max |0x092C| after static drift compensation
  std::uint32_t dc_static_frames{0};      // static drift compensation frames sent
  std::uint64_t sync0_start{0};           // system time of the first SYNC0
  hal::Nanoseconds started_at{0};
  hal::Nanoseconds safe_op_at{0};
  hal::Nanoseconds op_at{0};              // set by cycle() when every slave reached OP
  std::uint64_t frames{0};                // frames exchanged during bring-up
};

struct CycleResult {
  std::uint64_t cycle{0};
  MasterState state{MasterState::idle};
  bool frame_received{false};
  hal::Nanoseconds sent_at{0};
  hal::Nanoseconds received_at{0};
  SlaveMask valid{0};        // slaves whose inputs this frame brought
  SlaveMask out{0};          // slaves out of the exchange (not operated, lost, not operational, restored)
  std::array<std::uint16_t, kMaxBranches> branch_wkc{};
  std::array<std::uint16_t, kMaxBranches> expected_wkc{};
  std::uint64_t reference_time{0};       // DC system time of the reference as the frame passed it
  hal::Nanoseconds dc_phase_error{0};    // frame's phase error in the SYNC0 period
  hal::Nanoseconds next_wakeup{0};       // when to call cycle() next (master clock)
};

}  // namespace rescue::ecat
