// A type-erased, read-only view of a machine definition's tables (names, sentences, rows), built at
// compile time from the definition itself. The documentation writers (fsm/engine/table_docs.hpp) take this
// view, so the diagrams and tables in docs/ are printed from the very tables the firmware runs.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"
#include "fsm/engine/engine.hpp"

namespace rescue::fsm {

struct StateView {
  const char* name;
  const char* meaning;
  const char* entry_text;  // "" when the state has no entry action
  const char* exit_text;   // "" when the state has no exit action
};

struct InputView {
  const char* name;
  const char* meaning;
};

struct RowView {
  std::uint16_t from;
  std::uint16_t input;
  std::uint16_t to;
  const char* guard_text;   // "" when the row has no guard
  const char* action_text;  // "" when the row has no action
};

struct MachineView {
  const char* name;
  std::size_t initial;
  Span<const StateView> states;
  Span<const InputView> inputs;
  Span<const RowView> rows;
};

// The views take the documenting sentences only: a guard or action is documented by its text (the
// engine's convention: a function always comes with its sentence). Function pointers are not compared
// here because GCC cannot fold such comparisons at compile time in sanitizer builds.
namespace view_detail {

template <typename Def>
constexpr std::array<StateView, state_count<Def>()> make_states() noexcept {
  std::array<StateView, state_count<Def>()> out{};
  for (std::size_t s = 0; s < out.size(); ++s) {
    const auto& spec = Def::kStates[s];
    out[s] = StateView{spec.name, spec.meaning, spec.on_entry.text, spec.on_exit.text};
  }
  return out;
}

template <typename Def>
constexpr std::array<InputView, input_count<Def>()> make_inputs() noexcept {
  std::array<InputView, input_count<Def>()> out{};
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = InputView{Def::kInputs[i].name, Def::kInputs[i].meaning};
  return out;
}

template <typename Def>
constexpr std::array<RowView, Def::kRows.size()> make_rows() noexcept {
  std::array<RowView, Def::kRows.size()> out{};
  for (std::size_t r = 0; r < out.size(); ++r) {
    const auto& row = Def::kRows[r];
    out[r] = RowView{static_cast<std::uint16_t>(index_of(row.from)), static_cast<std::uint16_t>(index_of(row.input)),
                     static_cast<std::uint16_t>(index_of(row.to)), row.guard.text, row.action.text};
  }
  return out;
}

}  // namespace view_detail

// ViewOf<Def>::view(): the view of a definition, its arrays in static storage.
template <typename Def>
struct ViewOf {
  static constexpr std::array<StateView, state_count<Def>()> kStates = view_detail::make_states<Def>();
  static constexpr std::array<InputView, input_count<Def>()> kInputs = view_detail::make_inputs<Def>();
  static constexpr std::array<RowView, Def::kRows.size()> kRows = view_detail::make_rows<Def>();
  static constexpr MachineView view() noexcept {
    return MachineView{Def::kName, index_of(Def::kInitial), Span<const StateView>(kStates),
                       Span<const InputView>(kInputs), Span<const RowView>(kRows)};
  }
};

}  // namespace rescue::fsm
