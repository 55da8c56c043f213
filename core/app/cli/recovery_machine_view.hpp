// The master's online-recovery table (ecat/master/slave_recovery.hpp) seen through the fsm docs
// writers' MachineView, so `rescue-motion docs fsm` prints it like the machines in fsm/ (ecat/ does
// not include fsm/; the program may include both).
#pragma once

#include <array>

#include "ecat/master/slave_recovery.hpp"
#include "fsm/engine/machine_view.hpp"

namespace rescue::app {
namespace recovery_view_detail {

using Table = ecat::SlaveRecoveryTable;

constexpr std::array<fsm::StateView, ecat::kRecoveryStateCount> make_states() noexcept {
  std::array<fsm::StateView, ecat::kRecoveryStateCount> out{};
  for (std::size_t s = 0; s < out.size(); ++s) out[s] = fsm::StateView{Table::kStates[s].name, Table::kStates[s].meaning, "", ""};
  return out;
}

constexpr std::array<fsm::InputView, ecat::kRecoveryInputCount> make_inputs() noexcept {
  std::array<fsm::InputView, ecat::kRecoveryInputCount> out{};
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = fsm::InputView{Table::kInputs[i].name, Table::kInputs[i].meaning};
  return out;
}

constexpr std::array<fsm::RowView, Table::kRows.size()> make_rows() noexcept {
  std::array<fsm::RowView, Table::kRows.size()> out{};
  for (std::size_t r = 0; r < out.size(); ++r) {
    const ecat::RecoveryRow& row = Table::kRows[r];
    out[r] = fsm::RowView{static_cast<std::uint16_t>(row.from), static_cast<std::uint16_t>(row.input),
                          static_cast<std::uint16_t>(row.to), row.guard, row.action};
  }
  return out;
}

}  // namespace recovery_view_detail

struct RecoveryMachineView {
  static constexpr std::array<fsm::StateView, ecat::kRecoveryStateCount> kStates = recovery_view_detail::make_states();
  static constexpr std::array<fsm::InputView, ecat::kRecoveryInputCount> kInputs = recovery_view_detail::make_inputs();
  static constexpr std::array<fsm::RowView, ecat::SlaveRecoveryTable::kRows.size()> kRows = recovery_view_detail::make_rows();
  static constexpr fsm::MachineView view() noexcept {
    return fsm::MachineView{ecat::SlaveRecoveryTable::kName, static_cast<std::size_t>(ecat::SlaveRecoveryTable::kInitial),
                            Span<const fsm::StateView>(kStates), Span<const fsm::InputView>(kInputs),
                            Span<const fsm::RowView>(kRows)};
  }
};

}  // namespace rescue::app
