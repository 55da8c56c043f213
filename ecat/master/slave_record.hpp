// Everything the master keeps about one planned slave, in one record (one array of them, indexed
// by position): its configuration and identity from bring-up, the AL state it last answered, and
// where each cyclic service that works on it stands (OP step, re-integration, online recovery, PDO
// set-up), and whether the operator parked it below OP (ctl states). A service reads and writes the parts it owns; nothing per slave lives elsewhere.
#pragma once

#include <array>
#include <cstdint>

#include "core/base/endian.hpp"
#include "ecat/link/network_plan.hpp"
#include "ecat/master/network_match.hpp"
#include "ecat/master/pdo_setup.hpp"
#include "ecat/master/slave_recovery.hpp"
#include "ecat/master/slave_setup.hpp"
#include "hal/time/clock.hpp"

namespace rescue::ecat {

// The AL status register and code the master read last from the slave (probes, OP step,
// re-integration, recovery); `read`: one was read since bring-up.
struct AlSeen {
  std::uint16_t status{0};
  std::uint16_t code{0};
  bool read{false};
};

// SAFE-OP -> OP while cycling (op_step_service.hpp): write OP, watch AL status, acknowledge a
// refusal (in a frame of its own: the slave reads AL control asynchronously) and write OP again.
enum class OpStep : std::uint8_t { request, wait, acknowledge };
struct OpProgress {
  OpStep step{OpStep::request};
  std::uint8_t refusals{0};
  std::uint16_t al_status{0};  // as the OP step last read it (0: not yet)
  std::uint16_t al_code{0};
};

// Re-integration and re-arming (reintegration_service.hpp): FMMUs, AL status, acknowledge, OP request.
enum class ReStep : std::uint8_t { fmmus, status, acknowledge, request_op };

// Online recovery (recovery_service.hpp), the state of the slave_recovery table and what its steps keep.
struct RecoveryProgress {
  SlaveRecoveryMachine machine{};  // its state in the slave_recovery table
  std::uint8_t sub{0};             // step within the state
  std::uint8_t silent{0};          // datagrams in a row with working counter 0
  std::uint8_t words{0};           // SII words 0x08.. read so far
  bool acknowledge{false};         // next AL control write acknowledges an error
  bool plain_request{false};       // an acknowledging write left the error bit: ask for the state alone
  bool withdraw{false};            // searching: first write its station address back to 0
  bool lost_address{false};        // found with station address 0: its power was cycled
  bool by_address{false};          // searching: the next search reads 0x0010 by its own station address
  std::uint8_t scan{0};            // searching: which of its possible places the next APRD reads
  std::uint16_t handover{0};       // withdrawing: the station address written instead of 0 (the device's owner)
  std::uint8_t failures{0};        // failed attempts in a row (back-off), 0 after a recovery
  std::uint8_t bounces{0};         // attempts in a row that lost the device again (gone)
  hal::Nanoseconds changed_at{0};  // when it entered its current state
  std::uint16_t adp{0};            // auto-increment address it was found at
  std::uint8_t sdos_pending{0};    // start-up SDOs: the owner's transfer in flight (0 or 1)
  std::uint16_t sdo_next{0};       // the next of MasterOptions::startup_sdos to look at
  bool sdo_refused{false};
  hal::Nanoseconds deadline{0};
  std::array<std::uint16_t, 8> sii{};  // SII words 0x08..0x0F
  std::uint64_t offset{0};         // new system time offset (clock)
  std::uint64_t started_cycle{0};

  RecoveryState state() const noexcept { return machine.state(); }
};

struct SlaveRecord {
  SlaveSetup setup{};
  FoundSlave identity{};   // as its SII gave it at bring-up, when `identified`
  bool identified{false};  // it answered at bring-up and was matched to this position
  AlSeen al{};
  OpProgress op{};
  ReStep re{ReStep::fmmus};
  RecoveryProgress recovery{};
  PdoSetup pdo{};  // bring-up and recovery: its PDO mapping
  // ctl states took it below OP (slave_state_service.hpp): the online recovery leaves it alone
  // until the operator asks for OP.
  bool parked{false};

  // An answer of FPRD 0x0130 (AL status, reserved, AL status code).
  void note_al_status(const std::uint8_t* data) noexcept {
    al = AlSeen{load_le16(data), load_le16(data + 4), true};
  }
};

using SlaveRecords = std::array<SlaveRecord, kMaxSlaves>;

}  // namespace rescue::ecat
