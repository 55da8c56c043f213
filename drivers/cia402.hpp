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
// The fsm/ engine (a generic table-driven engine) had not landed on main when this was written;
// the table below has the same shape (from, input, to) and can move onto it unchanged.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

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

struct Transition {
  State from;
  Command command;
  State to;
  std::uint8_t number;  // CiA 402 transition number (0: staying in the state)
};

// clang-format off
inline constexpr std::array<Transition, 29> kTransitions{{
  {State::not_ready_to_switch_on, Command::self_test_done,   State::switch_on_disabled,    1},
  {State::switch_on_disabled,     Command::shutdown,         State::ready_to_switch_on,    2},
  {State::switch_on_disabled,     Command::disable_voltage,  State::switch_on_disabled,    0},
  {State::switch_on_disabled,     Command::quick_stop,       State::switch_on_disabled,    0},
  {State::ready_to_switch_on,     Command::switch_on,        State::switched_on,           3},
  {State::ready_to_switch_on,     Command::enable_operation, State::operation_enabled,     3},  // 3 then 4
  {State::ready_to_switch_on,     Command::shutdown,         State::ready_to_switch_on,    0},
  {State::ready_to_switch_on,     Command::disable_voltage,  State::switch_on_disabled,    7},
  {State::ready_to_switch_on,     Command::quick_stop,       State::switch_on_disabled,    7},
  {State::switched_on,            Command::enable_operation, State::operation_enabled,     4},
  {State::switched_on,            Command::switch_on,        State::switched_on,           0},
  {State::switched_on,            Command::shutdown,         State::ready_to_switch_on,    6},
  {State::switched_on,            Command::disable_voltage,  State::switch_on_disabled,   10},
  {State::switched_on,            Command::quick_stop,       State::switch_on_disabled,   10},
  {State::operation_enabled,      Command::switch_on,        State::switched_on,           5},  // disable operation
  {State::operation_enabled,      Command::enable_operation, State::operation_enabled,     0},
  {State::operation_enabled,      Command::shutdown,         State::ready_to_switch_on,    8},
  {State::operation_enabled,      Command::disable_voltage,  State::switch_on_disabled,    9},
  {State::operation_enabled,      Command::quick_stop,       State::quick_stop_active,    11},
  {State::quick_stop_active,      Command::quick_stop,       State::quick_stop_active,     0},
  {State::quick_stop_active,      Command::disable_voltage,  State::switch_on_disabled,   12},
  {State::quick_stop_active,      Command::stopped,          State::switch_on_disabled,   12},
  {State::fault_reaction_active,  Command::stopped,          State::fault,                14},
  {State::fault,                  Command::fault_reset,      State::switch_on_disabled,   15},
  {State::fault,                  Command::disable_voltage,  State::fault,                 0},
  {State::fault,                  Command::quick_stop,       State::fault,                 0},
  {State::fault,                  Command::shutdown,         State::fault,                 0},  // masters send it with the reset
  {State::fault_reaction_active,  Command::fault_detected,   State::fault_reaction_active, 0},
  {State::fault,                  Command::fault_detected,   State::fault,                 0},
}};
// clang-format on

// The row for (state, command), or nullptr. fault_detected from any state but the fault states
// is transition 13 (not listed per state above); see find_transition.
const Transition* find_transition(State from, Command command) noexcept;

// The state machine of one drive: current state, the last controlword (for the reset edge) and
// counters of refused commands.
class StateMachine {
 public:
  State state() const noexcept { return state_; }
  // Applies a controlword; returns true when the command was accepted (or there was none).
  bool apply_controlword(std::uint16_t controlword) noexcept;
  // Applies an internal event (self_test_done, fault_detected, stopped).
  bool apply(Command command) noexcept;
  std::uint32_t refused_count() const noexcept { return refused_; }
  std::uint8_t last_transition() const noexcept { return last_transition_; }
  std::uint16_t previous_controlword() const noexcept { return previous_controlword_; }
  // Guard of transition 15: a fault reset is refused while the fault's cause is still present.
  void set_fault_reset_allowed(bool allowed) noexcept { fault_reset_allowed_ = allowed; }

 private:
  State state_{State::not_ready_to_switch_on};
  std::uint16_t previous_controlword_{0};
  std::uint32_t refused_{0};
  std::uint8_t last_transition_{0};
  bool fault_reset_allowed_{true};
};

const char* to_string(State state) noexcept;
const char* to_string(Command command) noexcept;

}  // namespace rescue::drivers::cia402
