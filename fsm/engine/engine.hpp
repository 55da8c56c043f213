// A small generic engine for state machines written as constexpr tables.
//
// A machine is a definition type (see "Definition" below) holding three constexpr tables: its
// states (with optional entry/exit actions), its inputs, and its transition rows (from, input, to,
// optional guard, optional action). Machine<Def> is the running instance: one state byte and a few
// counters, no heap, no pointers to the context, so arrays of them (one per joint, one per slave)
// can live in fixed memory and be copied freely.
//
// dispatch(ctx, input) finds the row for (current state, input) through a dense [state][input]
// index built at compile time (O(1), no search), then:
//   1. no row                -> refused (Refusal::not_in_table), counted, nothing runs;
//   2. row guard says false  -> refused (Refusal::guard_failed), counted, nothing runs;
//   3. otherwise: exit action of `from` (only if the state changes), the row's action,
//      the state becomes `to`, entry action of `to` (only if the state changes).
// Refusals are returned as a Status (Errc::refused; detail0 = state, detail1 = input) and kept in
// last_refusal(): a transition that is not in the table is never silently ignored.
//
// Time per event is bounded: one index lookup plus at most four calls through function pointers
// (guard, exit, action, entry) whose own cost is the definition's business.
//
// Definition (a struct with only static constexpr members):
//   struct MyMachine {
//     using State = ...;    // enum class, values 0..N-1 in kStates order
//     using Input = ...;    // enum class, values 0..M-1 in kInputs order
//     using Context = ...;  // what guards read and actions write
//     static constexpr const char* kName = "my_machine";
//     static constexpr State kInitial = State::...;
//     static constexpr std::array<fsm::StateSpec<State, Context>, N> kStates{{...}};
//     static constexpr std::array<fsm::InputSpec<Input>, M> kInputs{{...}};
//     static constexpr std::array<fsm::Row<State, Input, Context>, R> kRows{{...}};
//   };
// check_definition<Def>() verifies the tables at compile time (Machine<Def> static_asserts it).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"

namespace rescue::fsm {

template <typename Context>
using GuardFn = bool (*)(const Context&) noexcept;
template <typename Context>
using ActionFn = void (*)(Context&) noexcept;

// A guard or action with the sentence that documents it (used by the generated docs). A function
// always comes with its sentence, and no function means "" (tests check every documented machine).
template <typename Context>
struct Guard {
  GuardFn<Context> fn{nullptr};
  const char* text{""};
};
template <typename Context>
struct Action {
  ActionFn<Context> fn{nullptr};
  const char* text{""};
};

template <typename State, typename Context>
struct StateSpec {
  State state;
  const char* name;
  const char* meaning;
  Action<Context> on_entry{};
  Action<Context> on_exit{};
};

template <typename Input>
struct InputSpec {
  Input input;
  const char* name;
  const char* meaning;
};

template <typename State, typename Input, typename Context>
struct Row {
  State from;
  Input input;
  State to;
  Guard<Context> guard{};    // no fn: always allowed
  Action<Context> action{};  // no fn: nothing to do
};

enum class DefinitionCheck : std::uint8_t {
  ok,
  states_not_in_enum_order,  // kStates[i].state must have value i
  inputs_not_in_enum_order,  // kInputs[i].input must have value i
  row_state_out_of_range,
  row_input_out_of_range,
  initial_out_of_range,
  duplicate_row,  // two rows for one (state, input): the machine would not be deterministic
  too_many_rows,  // the index stores row numbers in 16 bits
};

constexpr std::uint16_t kNoRow = 0xFFFF;

template <typename Def>
constexpr std::size_t state_count() noexcept {
  return Def::kStates.size();
}
template <typename Def>
constexpr std::size_t input_count() noexcept {
  return Def::kInputs.size();
}
template <typename E>
constexpr std::size_t index_of(E value) noexcept {
  return static_cast<std::size_t>(value);
}

template <typename Def>
constexpr DefinitionCheck check_definition() noexcept {
  constexpr std::size_t ns = state_count<Def>();
  constexpr std::size_t ni = input_count<Def>();
  for (std::size_t s = 0; s < ns; ++s) {
    if (index_of(Def::kStates[s].state) != s) return DefinitionCheck::states_not_in_enum_order;
  }
  for (std::size_t i = 0; i < ni; ++i) {
    if (index_of(Def::kInputs[i].input) != i) return DefinitionCheck::inputs_not_in_enum_order;
  }
  if (index_of(Def::kInitial) >= ns) return DefinitionCheck::initial_out_of_range;
  if (Def::kRows.size() >= kNoRow) return DefinitionCheck::too_many_rows;
  for (std::size_t r = 0; r < Def::kRows.size(); ++r) {
    const auto& row = Def::kRows[r];
    if (index_of(row.from) >= ns || index_of(row.to) >= ns) return DefinitionCheck::row_state_out_of_range;
    if (index_of(row.input) >= ni) return DefinitionCheck::row_input_out_of_range;
    for (std::size_t k = 0; k < r; ++k) {
      if (Def::kRows[k].from == row.from && Def::kRows[k].input == row.input) return DefinitionCheck::duplicate_row;
    }
  }
  return DefinitionCheck::ok;
}

// Dense [state][input] -> row number (kNoRow when the pair is not in the table), built at compile time.
template <typename Def>
constexpr std::array<std::uint16_t, state_count<Def>() * input_count<Def>()> build_index() noexcept {
  std::array<std::uint16_t, state_count<Def>() * input_count<Def>()> index{};
  for (auto& cell : index) cell = kNoRow;
  for (std::size_t r = 0; r < Def::kRows.size(); ++r) {
    const auto& row = Def::kRows[r];
    index[index_of(row.from) * input_count<Def>() + index_of(row.input)] = static_cast<std::uint16_t>(r);
  }
  return index;
}

enum class Refusal : std::uint8_t { none, not_in_table, guard_failed };

const char* to_string(Refusal refusal) noexcept;

// The static `what` strings of refusals, so callers can tell them apart without string compares.
constexpr const char* kRefusedNotInTable = "transition not in table";
constexpr const char* kRefusedByGuard = "guard refused transition";

template <typename Def>
class Machine {
 public:
  using State = typename Def::State;
  using Input = typename Def::Input;
  using Context = typename Def::Context;

  static_assert(check_definition<Def>() == DefinitionCheck::ok, "state machine tables are inconsistent");
  static constexpr std::array<std::uint16_t, state_count<Def>() * input_count<Def>()> kIndex = build_index<Def>();

  struct RefusalRecord {
    State state{Def::kInitial};
    Input input{};
    Refusal why{Refusal::none};
  };

  constexpr Machine() noexcept = default;
  constexpr explicit Machine(State initial) noexcept : state_(initial) {}

  State state() const noexcept { return state_; }

  // The row (current state, input) would take, or nullptr when the table has none. No side effects.
  static constexpr const Row<State, Input, Context>* find_row(State from, Input input) noexcept {
    const std::size_t s = index_of(from);
    const std::size_t i = index_of(input);
    if (s >= state_count<Def>() || i >= input_count<Def>()) return nullptr;
    const std::uint16_t r = kIndex[s * input_count<Def>() + i];
    return r == kNoRow ? nullptr : &Def::kRows[r];
  }

  // Would `input` be accepted now (row exists and its guard passes)? No side effects.
  bool accepts(const Context& ctx, Input input) const noexcept {
    const auto* row = find_row(state_, input);
    return row != nullptr && (row->guard.fn == nullptr || row->guard.fn(ctx));
  }

  // Applies `input`; see the file comment for the order of guard, exit, action and entry.
  Status dispatch(Context& ctx, Input input) noexcept {
    const auto* row = find_row(state_, input);
    if (row == nullptr) return refuse(input, Refusal::not_in_table, kRefusedNotInTable);
    if (row->guard.fn != nullptr && !row->guard.fn(ctx)) return refuse(input, Refusal::guard_failed, kRefusedByGuard);
    const bool changes = row->to != state_;
    if (changes) run(spec(state_).on_exit, ctx);
    run(row->action, ctx);
    state_ = row->to;
    if (changes) run(spec(state_).on_entry, ctx);
    ++accepted_;
    return Status::success();
  }

  std::uint32_t accepted_count() const noexcept { return accepted_; }
  std::uint32_t refused_count() const noexcept { return refused_; }
  const RefusalRecord& last_refusal() const noexcept { return last_refusal_; }

  static const char* state_name(State s) noexcept {
    return index_of(s) < state_count<Def>() ? Def::kStates[index_of(s)].name : "?";
  }
  static const char* input_name(Input i) noexcept {
    return index_of(i) < input_count<Def>() ? Def::kInputs[index_of(i)].name : "?";
  }

 private:
  static constexpr const StateSpec<State, Context>& spec(State s) noexcept { return Def::kStates[index_of(s)]; }
  static void run(const Action<Context>& action, Context& ctx) noexcept {
    if (action.fn != nullptr) action.fn(ctx);
  }
  Status refuse(Input input, Refusal why, const char* what) noexcept {
    ++refused_;
    last_refusal_ = RefusalRecord{state_, input, why};
    return make_error(Errc::refused, what, static_cast<std::uint32_t>(index_of(state_)),
                      static_cast<std::uint32_t>(index_of(input)));
  }

  State state_{Def::kInitial};
  std::uint32_t accepted_{0};
  std::uint32_t refused_{0};
  RefusalRecord last_refusal_{};
};

}  // namespace rescue::fsm
