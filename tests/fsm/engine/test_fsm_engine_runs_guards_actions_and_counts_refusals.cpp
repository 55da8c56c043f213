// The generic engine on its own, with a machine it was not written for: the CiA 402 drive power
// state machine (the drive's "Power Drive System" states), as the simulated drive could express it.
#include <gtest/gtest.h>

#include <array>
#include <cstring>

#include "fsm/engine/engine.hpp"

namespace rescue::fsm {
namespace {

enum class Power : std::uint8_t { switch_on_disabled, ready_to_switch_on, switched_on, operation_enabled, fault };
enum class Command : std::uint8_t { shutdown, switch_on, enable_operation, disable_voltage, fault_detected, fault_reset };

// Every call the machine makes is appended to the trace, so tests can check the order.
struct DriveContext {
  bool fault_cause_present{false};
  mutable int guard_calls{0};  // guards see a const context; counting them is test bookkeeping
  std::array<char, 32> trace{};
  std::size_t trace_len{0};
  void note(char c) noexcept {
    if (trace_len < trace.size() - 1) trace[trace_len++] = c;
  }
  const char* text() const noexcept { return trace.data(); }
};

struct Cia402Power {
  using State = Power;
  using Input = Command;
  using Context = DriveContext;
  static constexpr const char* kName = "cia402_power";
  static constexpr State kInitial = Power::switch_on_disabled;

  static constexpr Guard<Context> kCauseGone{[](const Context& c) noexcept {
                                               ++c.guard_calls;
                                               return !c.fault_cause_present;
                                             },
                                             "only if the fault cause is gone"};
  static constexpr Action<Context> kEnterOp{[](Context& c) noexcept { c.note('E'); }, "enter"};
  static constexpr Action<Context> kExitOp{[](Context& c) noexcept { c.note('X'); }, "exit"};
  static constexpr Action<Context> kEnterFault{[](Context& c) noexcept { c.note('F'); }, "fault entry"};
  static constexpr Action<Context> kRowAction{[](Context& c) noexcept { c.note('a'); }, "row action"};

  static constexpr std::array<StateSpec<State, Context>, 5> kStates{{
      {Power::switch_on_disabled, "SwitchOnDisabled", "", {}, {}},
      {Power::ready_to_switch_on, "ReadyToSwitchOn", "", {}, {}},
      {Power::switched_on, "SwitchedOn", "", {}, {}},
      {Power::operation_enabled, "OperationEnabled", "", kEnterOp, kExitOp},
      {Power::fault, "Fault", "", kEnterFault, {}},
  }};
  static constexpr std::array<InputSpec<Input>, 6> kInputs{{
      {Command::shutdown, "shutdown", ""},
      {Command::switch_on, "switch_on", ""},
      {Command::enable_operation, "enable_operation", ""},
      {Command::disable_voltage, "disable_voltage", ""},
      {Command::fault_detected, "fault_detected", ""},
      {Command::fault_reset, "fault_reset", ""},
  }};
  static constexpr std::array<Row<State, Input, Context>, 9> kRows{{
      {Power::switch_on_disabled, Command::shutdown, Power::ready_to_switch_on, {}, {}},
      {Power::ready_to_switch_on, Command::switch_on, Power::switched_on, {}, {}},
      {Power::switched_on, Command::enable_operation, Power::operation_enabled, {}, kRowAction},
      {Power::operation_enabled, Command::enable_operation, Power::operation_enabled, {}, kRowAction},
      {Power::operation_enabled, Command::disable_voltage, Power::switch_on_disabled, {}, kRowAction},
      {Power::operation_enabled, Command::fault_detected, Power::fault, {}, kRowAction},
      {Power::switched_on, Command::fault_detected, Power::fault, {}, {}},
      {Power::ready_to_switch_on, Command::fault_detected, Power::fault, {}, {}},
      {Power::fault, Command::fault_reset, Power::switch_on_disabled, kCauseGone, {}},
  }};
};

using Drive = Machine<Cia402Power>;

Drive enabled_drive(DriveContext& ctx) {
  Drive m;
  EXPECT_TRUE(m.dispatch(ctx, Command::shutdown).ok());
  EXPECT_TRUE(m.dispatch(ctx, Command::switch_on).ok());
  EXPECT_TRUE(m.dispatch(ctx, Command::enable_operation).ok());
  return m;
}

TEST(FsmEngine, StartsInTheInitialStateAndFollowsTheTable) {
  DriveContext ctx;
  Drive m;
  EXPECT_EQ(m.state(), Power::switch_on_disabled);
  m = enabled_drive(ctx);
  EXPECT_EQ(m.state(), Power::operation_enabled);
  EXPECT_EQ(m.accepted_count(), 3u);
  EXPECT_EQ(m.refused_count(), 0u);
}

TEST(FsmEngine, RunsExitThenRowActionThenEntryInThatOrder) {
  DriveContext ctx;
  Drive m = enabled_drive(ctx);
  EXPECT_STREQ(ctx.text(), "aE");  // row action of enable_operation, then entry of OperationEnabled
  ASSERT_TRUE(m.dispatch(ctx, Command::fault_detected).ok());
  EXPECT_STREQ(ctx.text(), "aEXaF");  // exit OperationEnabled, row action, entry Fault
}

TEST(FsmEngine, SelfTransitionRunsRowActionButNotExitOrEntry) {
  DriveContext ctx;
  Drive m = enabled_drive(ctx);
  ASSERT_TRUE(m.dispatch(ctx, Command::enable_operation).ok());
  EXPECT_EQ(m.state(), Power::operation_enabled);
  EXPECT_STREQ(ctx.text(), "aEa");
}

TEST(FsmEngine, RejectsPairNotInTableCountsAndReportsIt) {
  DriveContext ctx;
  Drive m;
  const Status s = m.dispatch(ctx, Command::enable_operation);  // SwitchOnDisabled has no such row
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::refused);
  EXPECT_STREQ(s.error().what, kRefusedNotInTable);
  EXPECT_EQ(s.error().detail0, static_cast<std::uint32_t>(Power::switch_on_disabled));
  EXPECT_EQ(s.error().detail1, static_cast<std::uint32_t>(Command::enable_operation));
  EXPECT_EQ(m.state(), Power::switch_on_disabled);
  EXPECT_EQ(m.refused_count(), 1u);
  EXPECT_EQ(m.accepted_count(), 0u);
  EXPECT_EQ(m.last_refusal().why, Refusal::not_in_table);
  EXPECT_EQ(m.last_refusal().state, Power::switch_on_disabled);
  EXPECT_EQ(m.last_refusal().input, Command::enable_operation);
  EXPECT_STREQ(ctx.text(), "");  // nothing ran
}

TEST(FsmEngine, GuardFalseRefusesWithoutSideEffectsGuardTrueTransitions) {
  DriveContext ctx;
  Drive m = enabled_drive(ctx);
  ASSERT_TRUE(m.dispatch(ctx, Command::fault_detected).ok());
  ctx.fault_cause_present = true;
  const Status refused = m.dispatch(ctx, Command::fault_reset);
  ASSERT_FALSE(refused.ok());
  EXPECT_STREQ(refused.error().what, kRefusedByGuard);
  EXPECT_EQ(m.state(), Power::fault);
  EXPECT_EQ(m.last_refusal().why, Refusal::guard_failed);
  EXPECT_EQ(m.refused_count(), 1u);
  ctx.fault_cause_present = false;
  EXPECT_TRUE(m.dispatch(ctx, Command::fault_reset).ok());
  EXPECT_EQ(m.state(), Power::switch_on_disabled);
  EXPECT_EQ(ctx.guard_calls, 2);
}

TEST(FsmEngine, AcceptsQueriesWithoutChangingAnything) {
  DriveContext ctx;
  Drive m;
  EXPECT_TRUE(m.accepts(ctx, Command::shutdown));
  EXPECT_FALSE(m.accepts(ctx, Command::fault_reset));
  EXPECT_EQ(m.state(), Power::switch_on_disabled);
  EXPECT_EQ(m.accepted_count() + m.refused_count(), 0u);
}

TEST(FsmEngine, DenseIndexHasOneCellPerPairAndPointsAtTheRightRows) {
  static_assert(Drive::kIndex.size() == 5 * 6, "one cell per (state, input)");
  std::size_t listed = 0;
  for (std::size_t s = 0; s < 5; ++s) {
    for (std::size_t i = 0; i < 6; ++i) {
      const auto* row = Drive::find_row(static_cast<Power>(s), static_cast<Command>(i));
      if (row == nullptr) continue;
      ++listed;
      EXPECT_EQ(index_of(row->from), s);
      EXPECT_EQ(index_of(row->input), i);
    }
  }
  EXPECT_EQ(listed, Cia402Power::kRows.size());
  EXPECT_EQ(Drive::find_row(static_cast<Power>(9), Command::shutdown), nullptr);  // out-of-range state
}

TEST(FsmEngine, NamesComeFromTheTables) {
  EXPECT_STREQ(Drive::state_name(Power::operation_enabled), "OperationEnabled");
  EXPECT_STREQ(Drive::input_name(Command::fault_reset), "fault_reset");
  EXPECT_STREQ(Drive::state_name(static_cast<Power>(42)), "?");
  EXPECT_STREQ(to_string(Refusal::guard_failed), "guard failed");
}

// Inconsistent tables are caught at compile time.
struct DuplicateRows : Cia402Power {
  static constexpr std::array<Row<State, Input, Context>, 2> kRows{{
      {Power::fault, Command::fault_reset, Power::switch_on_disabled, {}, {}},
      {Power::fault, Command::fault_reset, Power::fault, {}, {}},
  }};
};
struct StatesOutOfOrder : Cia402Power {
  static constexpr std::array<StateSpec<State, Context>, 2> kStates{{
      {Power::ready_to_switch_on, "b", "", {}, {}},
      {Power::switch_on_disabled, "a", "", {}, {}},
  }};
};
struct RowOutsideStates : Cia402Power {
  static constexpr std::array<StateSpec<State, Context>, 2> kStates{{
      {Power::switch_on_disabled, "a", "", {}, {}},
      {Power::ready_to_switch_on, "b", "", {}, {}},
  }};
};

TEST(FsmEngine, DefinitionCheckFindsInconsistentTables) {
  static_assert(check_definition<Cia402Power>() == DefinitionCheck::ok, "");
  static_assert(check_definition<DuplicateRows>() == DefinitionCheck::duplicate_row, "");
  static_assert(check_definition<StatesOutOfOrder>() == DefinitionCheck::states_not_in_enum_order, "");
  static_assert(check_definition<RowOutsideStates>() == DefinitionCheck::row_state_out_of_range, "");
  SUCCEED();
}

}  // namespace
}  // namespace rescue::fsm
