#include "drivers/cia402/cia402.hpp"

namespace rescue::drivers::cia402 {
Command decode_controlword(std::uint16_t controlword, std::uint16_t previous) noexcept {
  const bool reset_edge = (controlword & cw::kFaultReset) != 0 && (previous & cw::kFaultReset) == 0;
  if (reset_edge) return Command::fault_reset;
  if ((controlword & cw::kFaultReset) != 0) return Command::none;
  if ((controlword & cw::kEnableVoltage) == 0) return Command::disable_voltage;       // 0xxx xx0x
  if ((controlword & cw::kQuickStop) == 0) return Command::quick_stop;                // 0xxx x01x
  if ((controlword & cw::kSwitchOn) == 0) return Command::shutdown;                   // 0xxx x110
  if ((controlword & cw::kEnableOperation) == 0) return Command::switch_on;           // 0xxx 0111
  return Command::enable_operation;                                                   // 0xxx 1111
}

std::uint16_t statusword_bits(State state) noexcept {
  // Mains are always present in the simulated drive, so "voltage enabled" is set in every state
  // after power-up (as real drives report, e.g. 0x0250 in switch on disabled).
  switch (state) {
    case State::not_ready_to_switch_on: return sw::kRemote;
    case State::switch_on_disabled: return sw::kRemote | sw::kVoltageEnabled | sw::kSwitchOnDisabled;
    case State::ready_to_switch_on: return sw::kRemote | sw::kVoltageEnabled | sw::kQuickStop | sw::kReadyToSwitchOn;
    case State::switched_on:
      return sw::kRemote | sw::kVoltageEnabled | sw::kQuickStop | sw::kReadyToSwitchOn | sw::kSwitchedOn;
    case State::operation_enabled:
      return sw::kRemote | sw::kVoltageEnabled | sw::kQuickStop | sw::kReadyToSwitchOn | sw::kSwitchedOn |
             sw::kOperationEnabled;
    case State::quick_stop_active:
      return sw::kRemote | sw::kVoltageEnabled | sw::kReadyToSwitchOn | sw::kSwitchedOn | sw::kOperationEnabled;
    case State::fault_reaction_active:
      return sw::kRemote | sw::kVoltageEnabled | sw::kReadyToSwitchOn | sw::kSwitchedOn | sw::kOperationEnabled |
             sw::kFault;
    case State::fault: return sw::kRemote | sw::kVoltageEnabled | sw::kFault;
  }
  return sw::kRemote;
}

State state_from_statusword(std::uint16_t s) noexcept {
  const std::uint16_t shortm = s & sw::kStateMaskShort;
  const std::uint16_t longm = s & sw::kStateMaskLong;
  if (shortm == 0x0000) return State::not_ready_to_switch_on;
  if (shortm == 0x0040) return State::switch_on_disabled;
  if (longm == 0x0021) return State::ready_to_switch_on;
  if (longm == 0x0023) return State::switched_on;
  if (longm == 0x0027) return State::operation_enabled;
  if (longm == 0x0007) return State::quick_stop_active;
  if (shortm == 0x000F) return State::fault_reaction_active;
  if (shortm == 0x0008) return State::fault;
  return State::not_ready_to_switch_on;
}

bool StateMachine::apply_controlword(std::uint16_t controlword) noexcept {
  const Command command = decode_controlword(controlword, previous_controlword_);
  previous_controlword_ = controlword;
  if (command == Command::none) return true;
  return apply(command);
}

bool StateMachine::apply(Command command) noexcept {
  const State before = machine_.state();
  if (!machine_.dispatch(context_, command).ok()) return false;
  if (machine_.state() != before) last_transition_ = transition_number(before, machine_.state());
  return true;
}

const char* to_string(State state) noexcept {
  switch (state) {
    case State::not_ready_to_switch_on: return "not ready to switch on";
    case State::switch_on_disabled: return "switch on disabled";
    case State::ready_to_switch_on: return "ready to switch on";
    case State::switched_on: return "switched on";
    case State::operation_enabled: return "operation enabled";
    case State::quick_stop_active: return "quick stop active";
    case State::fault_reaction_active: return "fault reaction active";
    case State::fault: return "fault";
  }
  return "?";
}

const char* to_string(Command command) noexcept {
  switch (command) {
    case Command::none: return "none";
    case Command::shutdown: return "shutdown";
    case Command::switch_on: return "switch on / disable operation";
    case Command::enable_operation: return "enable operation";
    case Command::disable_voltage: return "disable voltage";
    case Command::quick_stop: return "quick stop";
    case Command::fault_reset: return "fault reset";
    case Command::self_test_done: return "self test done";
    case Command::fault_detected: return "fault detected";
    case Command::stopped: return "stopped";
  }
  return "?";
}

}  // namespace rescue::drivers::cia402
