// CiA 402 (IEC 61800-7-201) drive state machine: controlword -> state -> statusword, as a
// constexpr transition table (state, command) -> state. A (state, command) pair with no row is a
// refused command: the state does not change and the refusal is counted.
//
//                          +---------------------------(13) fault------------------------------+
//                          v                                                                    |
//   [Not ready to switch on] --(1) auto--> [Switch on disabled] <--(15) fault reset-- [Fault] <--(14) auto-- [Fault reaction active]
//                                            |  ^   ^   ^  ^
//                                 (2) shutdown  |   |   |  +--(12) disable voltage / stopped-- [Quick stop active]
//                                            v  |(7)|   |(10)                                         ^
//                                 [Ready to switch on] <--(6) shutdown-- [Switched on]                 | (11) quick stop
//                                            | (3) switch on ------------------^  | (4) enable op.    |
//                                            |                                    v                   |
//                                            +--(3+4) switch on + enable--> [Operation enabled] ------+
//                                                 (5) disable operation -> Switched on, (8) shutdown -> Ready, (9) disable voltage -> SOD
//
// Commands (controlword bits 7, 3, 2, 1, 0; x = any):
//   shutdown 0xxx x110 | switch on 0xxx 0111 | switch on + enable operation 0xxx 1111 |
//   disable voltage 0xxx xx0x | quick stop 0xxx x01x | disable operation 0xxx 0111 |
//   enable operation 0xxx 1111 | fault reset: bit 7 rising edge.
// Quick stop option code 2 (the CiA 402 default): decelerate on the quick-stop ramp, then Switch
// on disabled, so transition 16 (quick stop active -> operation enabled) is refused.
//
// The table runs on the generic engine of fsm/engine/engine.hpp (Cia402Definition below); the one guard
// is on transition 15: a fault reset is refused while the fault's cause persists.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fsm/engine/engine.hpp"

namespace rescue::drivers::cia402 {

enum class State : std::uint8_t {
  not_ready_to_switch_on,
  switch_on_disabled,
  ready_to_switch_on,
  switched_on,
  operation_enabled,
  quick_stop_active,
  fault_reaction_active,
  fault,
};

// What a controlword asks for (the command patterns of CiA 402 table 28), plus the drive's own
// internal events.
enum class Command : std::uint8_t {
  none,              // bit 7 held high: no command is formed
  shutdown,
  switch_on,         // also "disable operation" (same bits)
  enable_operation,  // also "switch on + enable operation" from Ready to switch on
  disable_voltage,
  quick_stop,
  fault_reset,       // rising edge of bit 7
  // internal events (not from the controlword)
  self_test_done,    // power-up initialisation finished (1)
  fault_detected,    // (13)
  stopped,           // the fault reaction / quick stop ramp reached standstill (12, 14)
};

// Statusword bits.
namespace sw {
constexpr std::uint16_t kReadyToSwitchOn = 1U << 0U;
constexpr std::uint16_t kSwitchedOn = 1U << 1U;
constexpr std::uint16_t kOperationEnabled = 1U << 2U;
constexpr std::uint16_t kFault = 1U << 3U;
constexpr std::uint16_t kVoltageEnabled = 1U << 4U;
constexpr std::uint16_t kQuickStop = 1U << 5U;  // 0 = quick stop active
constexpr std::uint16_t kSwitchOnDisabled = 1U << 6U;
constexpr std::uint16_t kWarning = 1U << 7U;
constexpr std::uint16_t kRemote = 1U << 9U;
constexpr std::uint16_t kTargetReached = 1U << 10U;
constexpr std::uint16_t kInternalLimitActive = 1U << 11U;
constexpr std::uint16_t kFollowsCommand = 1U << 12U;  // CSP/CSV/CST: the drive follows the target
constexpr std::uint16_t kFollowingError = 1U << 13U;  // CSP
// Masks that identify the state (CiA 402 table 30).
constexpr std::uint16_t kStateMaskShort = 0x004F;
constexpr std::uint16_t kStateMaskLong = 0x006F;
}  // namespace sw

// Controlword bits.
namespace cw {
constexpr std::uint16_t kSwitchOn = 1U << 0U;
constexpr std::uint16_t kEnableVoltage = 1U << 1U;
constexpr std::uint16_t kQuickStop = 1U << 2U;  // 0 = quick stop
constexpr std::uint16_t kEnableOperation = 1U << 3U;
constexpr std::uint16_t kFaultReset = 1U << 7U;
constexpr std::uint16_t kHalt = 1U << 8U;
// The standard command words a master writes.
constexpr std::uint16_t kShutdown = 0x0006;
constexpr std::uint16_t kSwitchOnCommand = 0x0007;
constexpr std::uint16_t kEnableOperationCommand = 0x000F;
constexpr std::uint16_t kDisableVoltage = 0x0000;
constexpr std::uint16_t kQuickStopCommand = 0x0002;
constexpr std::uint16_t kDisableOperation = 0x0007;
constexpr std::uint16_t kFaultResetCommand = 0x0080;
}  // namespace cw

// The command a controlword forms, given the previous controlword (for the bit-7 edge).
Command decode_controlword(std::uint16_t controlword, std::uint16_t previous) noexcept;

// The state bits of the statusword for `state` (bits 0-6; bit 9 "remote" is always set because
// the drive is controlled over EtherCAT).
std::uint16_t statusword_bits(State state) noexcept;
// The state a statusword shows (the master's view), or not_ready_to_switch_on for none.
State state_from_statusword(std::uint16_t statusword) noexcept;

// The CiA 402 number of the transition from `from` to `to` (0 when none: staying in a state).
constexpr std::uint8_t transition_number(State from, State to) noexcept {
  using S = State;
  if (from == to) return 0;
  switch (to) {
    case S::switch_on_disabled:
      switch (from) {
        case S::not_ready_to_switch_on: return 1;
        case S::ready_to_switch_on: return 7;
        case S::operation_enabled: return 9;
        case S::switched_on: return 10;
        case S::quick_stop_active: return 12;
        case S::fault: return 15;
        default: return 0;
      }
    case S::ready_to_switch_on: return from == S::switch_on_disabled ? 2 : from == S::switched_on ? 6 : 8;
    case S::switched_on: return from == S::ready_to_switch_on ? 3 : 5;
    case S::operation_enabled: return from == S::switched_on ? 4 : 3;  // from Ready: 3 and 4 at once
    case S::quick_stop_active: return 11;
    case S::fault_reaction_active: return 13;
    case S::fault: return 14;
    case S::not_ready_to_switch_on: return 0;
  }
  return 0;
}

// What the guard of transition 15 reads.
struct Context {
  bool fault_cause_persists{false};
};

// The machine as an fsm/ engine definition.
struct Cia402Definition {
  using State = cia402::State;
  using Input = cia402::Command;
  using Context = cia402::Context;
  using S = State;
  using C = Command;

  static constexpr const char* kName = "cia402";
  static constexpr State kInitial = S::not_ready_to_switch_on;

  static constexpr fsm::Guard<Context> kCauseCleared{
      [](const Context& c) noexcept { return !c.fault_cause_persists; }, "only if the fault's cause is gone"};

  // clang-format off
  static constexpr std::array<fsm::StateSpec<State, Context>, 8> kStates{{
    {S::not_ready_to_switch_on, "Not ready to switch on", "power-up self test; brake applied", {}, {}},
    {S::switch_on_disabled,     "Switch on disabled",     "power stage off, worm gear holds", {}, {}},
    {S::ready_to_switch_on,     "Ready to switch on",     "power stage off, ready to switch on", {}, {}},
    {S::switched_on,            "Switched on",            "power stage ready, no torque", {}, {}},
    {S::operation_enabled,      "Operation enabled",      "the motor follows the target of the mode", {}, {}},
    {S::quick_stop_active,      "Quick stop active",      "braking on the quick-stop ramp", {}, {}},
    {S::fault_reaction_active,  "Fault reaction active",  "a fault: braking, then power off", {}, {}},
    {S::fault,                  "Fault",                  "power off, 0x603F holds the error code", {}, {}},
  }};
  static constexpr std::array<fsm::InputSpec<Input>, 10> kInputs{{
    {C::none,             "none",             "bit 7 held high: no command"},
    {C::shutdown,         "shutdown",         "controlword 0xxx x110"},
    {C::switch_on,        "switch_on",        "controlword 0xxx 0111 (also disable operation)"},
    {C::enable_operation, "enable_operation", "controlword 0xxx 1111"},
    {C::disable_voltage,  "disable_voltage",  "controlword 0xxx xx0x"},
    {C::quick_stop,       "quick_stop",       "controlword 0xxx x01x"},
    {C::fault_reset,      "fault_reset",      "rising edge of controlword bit 7"},
    {C::self_test_done,   "self_test_done",   "power-up initialisation finished"},
    {C::fault_detected,   "fault_detected",   "a drive fault (injected, following error)"},
    {C::stopped,          "stopped",          "the braking ramp reached standstill"},
  }};
  static constexpr std::array<fsm::Row<State, Input, Context>, 35> kRows{{
    {S::not_ready_to_switch_on, C::self_test_done,   S::switch_on_disabled},
    {S::not_ready_to_switch_on, C::fault_detected,   S::fault_reaction_active},
    {S::switch_on_disabled,     C::shutdown,         S::ready_to_switch_on},
    {S::switch_on_disabled,     C::disable_voltage,  S::switch_on_disabled},
    {S::switch_on_disabled,     C::quick_stop,       S::switch_on_disabled},
    {S::switch_on_disabled,     C::fault_detected,   S::fault_reaction_active},
    {S::ready_to_switch_on,     C::switch_on,        S::switched_on},
    {S::ready_to_switch_on,     C::enable_operation, S::operation_enabled},
    {S::ready_to_switch_on,     C::shutdown,         S::ready_to_switch_on},
    {S::ready_to_switch_on,     C::disable_voltage,  S::switch_on_disabled},
    {S::ready_to_switch_on,     C::quick_stop,       S::switch_on_disabled},
    {S::ready_to_switch_on,     C::fault_detected,   S::fault_reaction_active},
    {S::switched_on,            C::enable_operation, S::operation_enabled},
    {S::switched_on,            C::switch_on,        S::switched_on},
    {S::switched_on,            C::shutdown,         S::ready_to_switch_on},
    {S::switched_on,            C::disable_voltage,  S::switch_on_disabled},
    {S::switched_on,            C::quick_stop,       S::switch_on_disabled},
    {S::switched_on,            C::fault_detected,   S::fault_reaction_active},
    {S::operation_enabled,      C::switch_on,        S::switched_on},
    {S::operation_enabled,      C::enable_operation, S::operation_enabled},
    {S::operation_enabled,      C::shutdown,         S::ready_to_switch_on},
    {S::operation_enabled,      C::disable_voltage,  S::switch_on_disabled},
    {S::operation_enabled,      C::quick_stop,       S::quick_stop_active},
    {S::operation_enabled,      C::fault_detected,   S::fault_reaction_active},
    {S::quick_stop_active,      C::quick_stop,       S::quick_stop_active},
    {S::quick_stop_active,      C::disable_voltage,  S::switch_on_disabled},
    {S::quick_stop_active,      C::stopped,          S::switch_on_disabled},
    {S::quick_stop_active,      C::fault_detected,   S::fault_reaction_active},
    {S::fault_reaction_active,  C::stopped,          S::fault},
    {S::fault_reaction_active,  C::fault_detected,   S::fault_reaction_active},
    {S::fault,                  C::fault_reset,      S::switch_on_disabled, kCauseCleared},
    {S::fault,                  C::disable_voltage,  S::fault},
    {S::fault,                  C::quick_stop,       S::fault},
    {S::fault,                  C::shutdown,         S::fault},  // masters send it with the reset
    {S::fault,                  C::fault_detected,   S::fault},
  }};
  // clang-format on
};

// The state machine of one drive: the engine's machine, the last controlword (for the reset
// edge) and the fault-reset guard's fact.
class StateMachine {
 public:
  using Machine = fsm::Machine<Cia402Definition>;

  State state() const noexcept { return machine_.state(); }
  // Applies a controlword; returns true when the command was accepted (or there was none).
  bool apply_controlword(std::uint16_t controlword) noexcept;
  // Applies a command or an internal event (self_test_done, fault_detected, stopped).
  bool apply(Command command) noexcept;
  std::uint32_t refused_count() const noexcept { return machine_.refused_count(); }
  std::uint8_t last_transition() const noexcept { return last_transition_; }
  // Guard of transition 15: a fault reset is refused while the fault's cause is still present.
  void set_fault_reset_allowed(bool allowed) noexcept { context_.fault_cause_persists = !allowed; }

 private:
  Machine machine_{};
  Context context_{};
  std::uint16_t previous_controlword_{0};
  std::uint8_t last_transition_{0};
};

const char* to_string(State state) noexcept;
const char* to_string(Command command) noexcept;

}  // namespace rescue::drivers::cia402
