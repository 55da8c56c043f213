// The master's online-recovery table (ecat/master/slave_recovery.hpp) seen through the fsm docs
// writers' MachineView, so `rescue-motion docs fsm` prints it like the machines in fsm/ (ecat/ does
// not include fsm/; the program may include both).
#pragma once

#include <array>

#include "ecat/master/slave_recovery.hpp"
#include "fsm/engine/machine_view.hpp"

namespace rescue::app {

struct RecoveryMachineView {
  using T = ecat::SlaveRecoveryTable;
  static constexpr std::array<fsm::StateView, ecat::kRecoveryStateCount> kStates = [] {
    std::array<fsm::StateView, ecat::kRecoveryStateCount> out{};
    for (std::size_t s = 0; s < out.size(); ++s) out[s] = fsm::StateView{T::kStates[s].name, T::kStates[s].meaning, "", ""};
    return out;
  }();
  static constexpr std::array<fsm::InputView, ecat::kRecoveryInputCount> kInputs = [] {
    std::array<fsm::InputView, ecat::kRecoveryInputCount> out{};
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = fsm::InputView{T::kInputs[i].name, T::kInputs[i].meaning};
    return out;
  }();
  static constexpr std::array<fsm::RowView, T::kRows.size()> kRows = [] {
    std::array<fsm::RowView, T::kRows.size()> out{};
    for (std::size_t r = 0; r < out.size(); ++r) {
      const ecat::RecoveryRow& row = T::kRows[r];
      out[r] = fsm::RowView{static_cast<std::uint16_t>(row.from), static_cast<std::uint16_t>(row.input),
                            static_cast<std::uint16_t>(row.to), row.guard, row.action};
    }
    return out;
  }();
  static constexpr fsm::MachineView view() noexcept {
    return fsm::MachineView{T::kName, static_cast<std::size_t>(T::kInitial), Span<const fsm::StateView>(kStates),
                            Span<const fsm::InputView>(kInputs), Span<const fsm::RowView>(kRows)};
  }
};

}  // namespace rescue::app
