#include "drivers/cia402/cia402_enable.hpp"

#include "drivers/cia402/cia402.hpp"

namespace rescue::drivers {

using cia402::State;
namespace cw = cia402::cw;

std::uint16_t controlword_towards_enabled(std::uint16_t statusword, std::uint16_t previous) noexcept {
  switch (cia402::state_from_statusword(statusword)) {
    case State::switch_on_disabled: return cw::kShutdown;
    case State::ready_to_switch_on: return cw::kSwitchOnCommand;
    case State::switched_on:
    case State::operation_enabled: return cw::kEnableOperationCommand;
    case State::fault:
      // A reset is the rising edge of bit 7: send it low for a cycle first if it was high.
      return (previous & cw::kFaultReset) != 0 ? cw::kDisableVoltage : cw::kFaultResetCommand;
    case State::quick_stop_active:
    case State::fault_reaction_active:
    case State::not_ready_to_switch_on: return cw::kDisableVoltage;
  }
  return cw::kDisableVoltage;
}

std::uint16_t controlword_towards_disabled(std::uint16_t statusword) noexcept {
  return cia402::state_from_statusword(statusword) == State::operation_enabled ? cw::kDisableOperation
                                                                                : cw::kDisableVoltage;
}

bool is_enabled(std::uint16_t statusword) noexcept {
  return cia402::state_from_statusword(statusword) == State::operation_enabled;
}

bool is_faulted(std::uint16_t statusword) noexcept {
  const State s = cia402::state_from_statusword(statusword);
  return s == State::fault || s == State::fault_reaction_active;
}

}  // namespace rescue::drivers
