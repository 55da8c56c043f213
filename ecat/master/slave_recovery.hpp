// Online recovery of a slave that returns while the others cycle (a power-cycled drive, a replaced
// cable, a reconnected branch): the state machine, a definition of the fsm engine
// (fsm/engine/engine.hpp). One fsm::Machine per slave (its SlaveRecord); the recovery service
// (ecat/master/recovery_service.cpp) feeds it inputs from the cyclic frame and does what each state
// says, one datagram per period and slave, at most MasterOptions::recovery_datagrams_per_cycle per
// period in all; the rows' actions and the states' entry are RecoveryActions (recovery_service.cpp).
// docs/master.md prints this very table (`rescue-motion docs fsm --machine slave_recovery`). A
// (state, input) pair without a row is refused by the engine and counted.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fsm/engine/engine.hpp"

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

class RecoveryService;

// What the machine's actions work on: the service and the slave whose machine it is.
struct RecoveryContext {
  RecoveryService& service;
  std::size_t position;
  RecoveryInput input;
};

// The machine's actions, each with the sentence the docs print (defined in recovery_service.cpp).
struct RecoveryActions {
  static void watch_position(RecoveryContext& ctx) noexcept;
  static void report_failed(RecoveryContext& ctx) noexcept;
  static void report_refused(RecoveryContext& ctx) noexcept;
  static void withdraw_address(RecoveryContext& ctx) noexcept;
  static void report_recovered(RecoveryContext& ctx) noexcept;
  // Entry of every state: its steps start from the first, its time and deadline are set, and what
  // the state needs first is prepared (SII words cleared, mailbox SMs, PDO set-up queued).
  static void enter_state(RecoveryContext& ctx) noexcept;
};

struct SlaveRecoveryTable {
  using State = RecoveryState;
  using Input = RecoveryInput;
  using Context = RecoveryContext;
  using S = RecoveryState;
  using I = RecoveryInput;
  using StateSpec = fsm::StateSpec<S, Context>;
  using Row = fsm::Row<S, I, Context>;
  using A = fsm::Action<Context>;
  static constexpr A kStart{&RecoveryActions::enter_state, "steps from the first; deadline recovery_step_timeout"};
  static constexpr A kStartIdentifying{&RecoveryActions::enter_state, "steps from the first; deadline recovery_step_timeout; SII words cleared"};
  static constexpr A kStartMailbox{&RecoveryActions::enter_state, "steps from the first; deadline recovery_step_timeout; its mailbox SMs to the mailbox client"};
  static constexpr A kStartSdos{&RecoveryActions::enter_state, "steps from the first; queue its PDO set-up and start-up SDOs (deadline per transfer)"};
  static constexpr A kStartFailed{&RecoveryActions::enter_state, "steps from the first; deadline the hold-off"};
  static constexpr A kWatch{&RecoveryActions::watch_position, "watch its position"};
  static constexpr A kFailed{&RecoveryActions::report_failed, "report recovery_failed"};
  static constexpr A kRefused{&RecoveryActions::report_refused, "report recovery_refused with the identity found"};
  static constexpr A kWithdraw{&RecoveryActions::withdraw_address, "station address withdrawn (FPWR 0x0010 = 0), or handed to the slave searched for whose identity it has"};
  static constexpr A kRecovered{&RecoveryActions::report_recovered, "back in the exchange, report recovered"};
  static constexpr const char* kName = "slave_recovery";
  static constexpr RecoveryState kInitial = S::idle;

  // clang-format off
  static constexpr std::array<StateSpec, kRecoveryStateCount> kStates{{
    {S::idle,         "Idle",         "in the exchange, or not planned to run", kStart},
    {S::searching,    "Searching",    "out of the exchange; FPRD 0x0010 by its own station address (two devices answering it: FPWR 0x0010 = 0 at it, both searched for again by place) (it kept it: a slave behind a power-cycled or reconnected one) and APRD 0x0010 at the places it may have, in turn (one search per period, rotating among the slaves searched for)", kStart},
    {S::addressing,   "Addressing",   "APWR 0x0010 by position: its station address (no other slave is written)", kStart},
    {S::resetting,    "Resetting",    "FPWR 0x0120 = INIT + acknowledge, FPRD 0x0130 until INIT", kStart},
    {S::identifying,  "Identifying",  "SII to ECAT (0x0500), then SII words 0x08..0x0F (vendor, product, revision, serial) through 0x0502..0x050F", kStartIdentifying},
    {S::mailbox,      "Mailbox",      "FPWR 0x0800: SM0/SM1 from its SII (slaves with a CoE mailbox)", kStartMailbox},
    {S::pre_op,       "PreOp",        "FPWR 0x0120 = PRE-OP, FPRD 0x0130 until PRE-OP", kStart},
    {S::startup_sdos, "StartupSdos",  "its PDO mapping (read; what differs written, read back) and its start-up SDOs (limits) through the cyclic mailbox channel, one transfer per slave at a time", kStartSdos},
    {S::process_data, "ProcessData",  "FPWR 0x0810: SM2/SM3, then FPWR 0x0600: FMMU0/FMMU1 as at bring-up", kStart},
    {S::clock,        "Clock",        "FPRD 0x0910..0x092F beside the frame's reference read, then FPWR 0x0920 offset + 0x0928 delay, FPWR 0x0930 loop restart", kStart},
    {S::sync0,        "Sync0",        "FPWR 0x0980 off, 0x09A0 cycle, 0x0990 start (in phase with the others), 0x0981 on", kStart},
    {S::safe_op,      "SafeOp",       "FPWR 0x0120 = SAFE-OP, FPRD 0x0130 until SAFE-OP (an error is acknowledged)", kStart},
    {S::op,           "Op",           "FPWR 0x0120 = OP, FPRD 0x0130 until OP (an error is acknowledged)", kStart},
    {S::refused,      "Refused",      "another device in its place: only its station address was written; watched by APRD until it leaves", kStart},
    {S::failed,       "Failed",       "a step timed out, or the device was lost in 3 attempts in a row; reported; waits the hold-off (doubling with each failure in a row, up to recovery_hold_off_max), then starts again from the search", kStartFailed},
  }};
  static constexpr std::array<fsm::InputSpec<I>, kRecoveryInputCount> kInputs{{
    {I::lost,                 "lost",                 "the link monitor has it out of the exchange (lost, restored, or not operational e.g. answering in INIT)"},
    {I::answered_unaddressed, "answered_unaddressed", "a device with station address 0 answers at a place it may have (taken by the first slave searched for that may be there; not when another slave is about to address it)"},
    {I::answered_addressed,   "answered_addressed",   "it answers by its own station address (configuration kept)"},
    {I::step_done,            "step_done",            "the state's writes were taken and its state confirmed"},
    {I::foreign,              "foreign",              "SII vendor, product or revision differ from the plan, and no slave searched for has this identity"},
    {I::not_this_one,         "not_this_one",         "another slave searched for has this identity (whatever its type), or same device type with another serial number than at bring-up"},
    {I::gone,                 "gone",                 "silent (working counter 0) for several periods in a row, or its station address answered by two devices (then withdrawn from both) (the third such attempt in a row counts as a timeout)"},
    {I::timeout,              "timeout",              "the state's deadline passed"},
    {I::retry,                "retry",                "the hold-off after a failure is over"},
  }};
  static constexpr std::array<Row, 39> kRows{{
    {S::idle,         I::lost,                 S::searching,    {}, kWatch},
    {S::searching,    I::answered_unaddressed, S::addressing,   {}, {}},
    {S::searching,    I::answered_addressed,   S::resetting,    {}, {}},
    {S::addressing,   I::step_done,            S::resetting,    {}, {}},
    {S::addressing,   I::gone,                 S::searching,    {}, {}},
    {S::addressing,   I::timeout,              S::failed,       {}, kFailed},
    {S::resetting,    I::step_done,            S::identifying,  {}, {}},
    {S::resetting,    I::gone,                 S::searching,    {}, {}},
    {S::resetting,    I::timeout,              S::failed,       {}, kFailed},
    {S::identifying,  I::step_done,            S::mailbox,      {}, {}},
    {S::identifying,  I::foreign,              S::refused,      {}, kRefused},
    {S::identifying,  I::not_this_one,         S::searching,    {}, kWithdraw},
    {S::identifying,  I::gone,                 S::searching,    {}, {}},
    {S::identifying,  I::timeout,              S::failed,       {}, kFailed},
    {S::mailbox,      I::step_done,            S::pre_op,       {}, {}},
    {S::mailbox,      I::gone,                 S::searching,    {}, {}},
    {S::pre_op,       I::step_done,            S::startup_sdos, {}, {}},
    {S::pre_op,       I::gone,                 S::searching,    {}, {}},
    {S::pre_op,       I::timeout,              S::failed,       {}, kFailed},
    {S::startup_sdos, I::step_done,            S::process_data, {}, {}},
    {S::startup_sdos, I::timeout,              S::failed,       {}, kFailed},
    {S::process_data, I::step_done,            S::clock,        {}, {}},
    {S::process_data, I::gone,                 S::searching,    {}, {}},
    {S::clock,        I::step_done,            S::sync0,        {}, {}},
    {S::clock,        I::gone,                 S::searching,    {}, {}},
    {S::clock,        I::timeout,              S::failed,       {}, kFailed},
    {S::sync0,        I::step_done,            S::safe_op,      {}, {}},
    {S::sync0,        I::gone,                 S::searching,    {}, {}},
    {S::sync0,        I::timeout,              S::failed,       {}, kFailed},
    {S::safe_op,      I::step_done,            S::op,           {}, {}},
    {S::safe_op,      I::gone,                 S::searching,    {}, {}},
    {S::safe_op,      I::timeout,              S::failed,       {}, kFailed},
    {S::op,           I::step_done,            S::idle,         {}, kRecovered},
    {S::op,           I::gone,                 S::searching,    {}, {}},
    {S::op,           I::timeout,              S::failed,       {}, kFailed},
    {S::refused,      I::gone,                 S::searching,    {}, {}},
    {S::failed,       I::retry,                S::searching,    {}, {}},
    {S::mailbox,      I::timeout,              S::failed,       {}, kFailed},
    {S::process_data, I::timeout,              S::failed,       {}, kFailed},
  }};
  // clang-format on
};

using SlaveRecoveryMachine = fsm::Machine<SlaveRecoveryTable>;

const char* to_string(RecoveryState state) noexcept;

}  // namespace rescue::ecat
