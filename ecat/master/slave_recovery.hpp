// Online recovery of a slave that returns while the others cycle (a power-cycled drive, a replaced
// cable, a reconnected branch): the state machine, as a table. One instance per slave; the master
// (ecat/master/master_recovery.cpp) drives it from the cyclic frame and does what each state says,
// one datagram per period and slave, at most MasterOptions::recovery_datagrams_per_cycle per period
// in all. docs/master.md prints this very table (`rescue-motion docs fsm --machine slave_recovery`).
//
// The table is plain data (ecat/ does not include fsm/); it has the fsm engine's shape (states with
// a meaning, inputs with a meaning, rows from/input/to/action) so the program's docs command prints
// it like the machines in fsm/. A (state, input) pair without a row is refused and counted.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace rescue::ecat {

enum class RecoveryState : std::uint8_t {
  idle = 0,
  searching,
  addressing,
  resetting,
  identifying,
  mailbox,
  pre_op,
  startup_sdos,
  process_data,
  clock,
  sync0,
  safe_op,
  op,
  refused,
  failed,
};
constexpr std::size_t kRecoveryStateCount = 15;

enum class RecoveryInput : std::uint8_t {
  lost = 0,
  answered_unaddressed,
  answered_addressed,
  step_done,
  foreign,
  not_this_one,
  gone,
  timeout,
  retry,
};
constexpr std::size_t kRecoveryInputCount = 9;

struct RecoveryStateSpec {
  RecoveryState state;
  const char* name;
  const char* meaning;
};
struct RecoveryInputSpec {
  RecoveryInput input;
  const char* name;
  const char* meaning;
};
struct RecoveryRow {
  RecoveryState from;
  RecoveryInput input;
  RecoveryState to;
  const char* guard;   // "" when none
  const char* action;  // "" when none
};

struct SlaveRecoveryTable {
  using S = RecoveryState;
  using I = RecoveryInput;
  static constexpr const char* kName = "slave_recovery";
  static constexpr RecoveryState kInitial = S::idle;

  // clang-format off
  static constexpr std::array<RecoveryStateSpec, kRecoveryStateCount> kStates{{
    {S::idle,         "Idle",         "in the exchange, or not planned to run"},
    {S::searching,    "Searching",    "out of the exchange; FPRD 0x0010 by its own station address (it kept it: a slave behind a power-cycled or reconnected one) and APRD 0x0010 at the places it may have, in turn (one search per period, rotating among the slaves searched for)"},
    {S::addressing,   "Addressing",   "APWR 0x0010 by position: its station address (no other slave is written)"},
    {S::resetting,    "Resetting",    "FPWR 0x0120 = INIT + acknowledge, FPRD 0x0130 until INIT"},
    {S::identifying,  "Identifying",  "SII to ECAT (0x0500), then SII words 0x08..0x0F (vendor, product, revision, serial) through 0x0502..0x050F"},
    {S::mailbox,      "Mailbox",      "FPWR 0x0800: SM0/SM1 from its SII (slaves with a CoE mailbox)"},
    {S::pre_op,       "PreOp",        "FPWR 0x0120 = PRE-OP, FPRD 0x0130 until PRE-OP"},
    {S::startup_sdos, "StartupSdos",  "its PDO mapping (read; what differs written, read back) and its start-up SDOs (limits) through the cyclic mailbox channel, one transfer per slave at a time"},
    {S::process_data, "ProcessData",  "FPWR 0x0810: SM2/SM3, then FPWR 0x0600: FMMU0/FMMU1 as at bring-up"},
    {S::clock,        "Clock",        "FPRD 0x0910..0x092F beside the frame's reference read, then FPWR 0x0920 offset + 0x0928 delay, FPWR 0x0930 loop restart"},
    {S::sync0,        "Sync0",        "FPWR 0x0980 off, 0x09A0 cycle, 0x0990 start (in phase with the others), 0x0981 on"},
    {S::safe_op,      "SafeOp",       "FPWR 0x0120 = SAFE-OP, FPRD 0x0130 until SAFE-OP (an error is acknowledged)"},
    {S::op,           "Op",           "FPWR 0x0120 = OP, FPRD 0x0130 until OP (an error is acknowledged)"},
    {S::refused,      "Refused",      "another device in its place: only its station address was written; watched by APRD until it leaves"},
    {S::failed,       "Failed",       "a step timed out, or the device was lost in 3 attempts in a row; reported; waits the hold-off (doubling with each failure in a row, up to recovery_hold_off_max), then starts again from the search"},
  }};
  static constexpr std::array<RecoveryInputSpec, kRecoveryInputCount> kInputs{{
    {I::lost,                 "lost",                 "the link monitor has it out of the exchange (lost, restored, or not operational e.g. answering in INIT)"},
    {I::answered_unaddressed, "answered_unaddressed", "a device with station address 0 answers at a place it may have (taken by the first slave searched for that may be there)"},
    {I::answered_addressed,   "answered_addressed",   "it answers by its own station address (configuration kept)"},
    {I::step_done,            "step_done",            "the state's writes were taken and its state confirmed"},
    {I::foreign,              "foreign",              "SII vendor, product or revision differ from the plan"},
    {I::not_this_one,         "not_this_one",         "same device type, another serial number than at bring-up"},
    {I::gone,                 "gone",                 "silent (working counter 0) for several periods in a row (the third such attempt in a row counts as a timeout)"},
    {I::timeout,              "timeout",              "the state's deadline passed"},
    {I::retry,                "retry",                "the hold-off after a failure is over"},
  }};
  static constexpr std::array<RecoveryRow, 39> kRows{{
    {S::idle,         I::lost,                 S::searching,    "", "watch its position"},
    {S::searching,    I::answered_unaddressed, S::addressing,   "", ""},
    {S::searching,    I::answered_addressed,   S::resetting,    "", ""},
    {S::addressing,   I::step_done,            S::resetting,    "", ""},
    {S::addressing,   I::gone,                 S::searching,    "", ""},
    {S::addressing,   I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::resetting,    I::step_done,            S::identifying,  "", ""},
    {S::resetting,    I::gone,                 S::searching,    "", ""},
    {S::resetting,    I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::identifying,  I::step_done,            S::mailbox,      "", ""},
    {S::identifying,  I::foreign,              S::refused,      "", "report recovery_refused with the identity found"},
    {S::identifying,  I::not_this_one,         S::searching,    "", "station address withdrawn (FPWR 0x0010 = 0), or handed to the slave searched for whose serial number it has"},
    {S::identifying,  I::gone,                 S::searching,    "", ""},
    {S::identifying,  I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::mailbox,      I::step_done,            S::pre_op,       "", ""},
    {S::mailbox,      I::gone,                 S::searching,    "", ""},
    {S::pre_op,       I::step_done,            S::startup_sdos, "", "queue its start-up SDOs"},
    {S::pre_op,       I::gone,                 S::searching,    "", ""},
    {S::pre_op,       I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::startup_sdos, I::step_done,            S::process_data, "", ""},
    {S::startup_sdos, I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::process_data, I::step_done,            S::clock,        "", ""},
    {S::process_data, I::gone,                 S::searching,    "", ""},
    {S::clock,        I::step_done,            S::sync0,        "", ""},
    {S::clock,        I::gone,                 S::searching,    "", ""},
    {S::clock,        I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::sync0,        I::step_done,            S::safe_op,      "", ""},
    {S::sync0,        I::gone,                 S::searching,    "", ""},
    {S::sync0,        I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::safe_op,      I::step_done,            S::op,           "", ""},
    {S::safe_op,      I::gone,                 S::searching,    "", ""},
    {S::safe_op,      I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::op,           I::step_done,            S::idle,         "", "back in the exchange, report recovered"},
    {S::op,           I::gone,                 S::searching,    "", ""},
    {S::op,           I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::refused,      I::gone,                 S::searching,    "", ""},
    {S::failed,       I::retry,                S::searching,    "", ""},
    {S::mailbox,      I::timeout,              S::failed,       "", "report recovery_failed"},
    {S::process_data, I::timeout,              S::failed,       "", "report recovery_failed"},
  }};
  // clang-format on

  // The row for (from, input), or nullptr: refused.
  static constexpr const RecoveryRow* find(RecoveryState from, RecoveryInput input) noexcept {
    for (const RecoveryRow& row : kRows) {
      // cppcheck-suppress useStlAlgorithm ; constexpr: std::find_if is constexpr only from C++20
      if (row.from == from && row.input == input) return &row;
    }
    return nullptr;
  }
};

// Every state's table entry sits at its own index, so the state's value indexes kStates.
constexpr bool recovery_table_is_ordered() noexcept {
  for (std::size_t s = 0; s < kRecoveryStateCount; ++s) {
    if (static_cast<std::size_t>(SlaveRecoveryTable::kStates[s].state) != s) return false;
  }
  for (std::size_t i = 0; i < kRecoveryInputCount; ++i) {
    if (static_cast<std::size_t>(SlaveRecoveryTable::kInputs[i].input) != i) return false;
  }
  return true;
}
static_assert(recovery_table_is_ordered(), "kStates/kInputs in enum order");

const char* to_string(RecoveryState state) noexcept;

}  // namespace rescue::ecat
