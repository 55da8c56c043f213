// CiA 402 state machine: every documented transition (1..15, 3+4) from the controlword commands
// and internal events, the statusword each state shows, and the commands each state refuses.
#include <gtest/gtest.h>

#include "drivers/cia402/cia402.hpp"

namespace rescue::drivers::cia402 {
namespace {

// Drives a fresh machine to `target` along the standard command sequence.
StateMachine machine_in(State target) {
  StateMachine m;
  EXPECT_TRUE(m.apply(Command::self_test_done));
  if (target == State::not_ready_to_switch_on) return StateMachine{};
  if (target == State::switch_on_disabled) return m;
  if (target == State::fault || target == State::fault_reaction_active) {
    EXPECT_TRUE(m.apply(Command::fault_detected));
    if (target == State::fault) {
      EXPECT_TRUE(m.apply(Command::stopped));
    }
    return m;
  }
  EXPECT_TRUE(m.apply_controlword(cw::kShutdown));
  if (target == State::ready_to_switch_on) return m;
  EXPECT_TRUE(m.apply_controlword(cw::kSwitchOnCommand));
  if (target == State::switched_on) return m;
  EXPECT_TRUE(m.apply_controlword(cw::kEnableOperationCommand));
  if (target == State::operation_enabled) return m;
  EXPECT_TRUE(m.apply_controlword(cw::kQuickStopCommand));
  return m;  // quick stop active
}

struct Case {
  State from;
  std::uint16_t controlword;
  State to;
  std::uint8_t number;
};

TEST(Cia402Transitions, EveryControlwordTransitionOfTheStandard) {
  const Case cases[] = {
      {State::switch_on_disabled, cw::kShutdown, State::ready_to_switch_on, 2},
      {State::ready_to_switch_on, cw::kSwitchOnCommand, State::switched_on, 3},
      {State::ready_to_switch_on, cw::kEnableOperationCommand, State::operation_enabled, 3},  // 3 + 4 at once
      {State::switched_on, cw::kEnableOperationCommand, State::operation_enabled, 4},
      {State::operation_enabled, cw::kDisableOperation, State::switched_on, 5},
      {State::switched_on, cw::kShutdown, State::ready_to_switch_on, 6},
      {State::ready_to_switch_on, cw::kQuickStopCommand, State::switch_on_disabled, 7},
      {State::ready_to_switch_on, cw::kDisableVoltage, State::switch_on_disabled, 7},
      {State::operation_enabled, cw::kShutdown, State::ready_to_switch_on, 8},
      {State::operation_enabled, cw::kDisableVoltage, State::switch_on_disabled, 9},
      {State::switched_on, cw::kDisableVoltage, State::switch_on_disabled, 10},
      {State::switched_on, cw::kQuickStopCommand, State::switch_on_disabled, 10},
      {State::operation_enabled, cw::kQuickStopCommand, State::quick_stop_active, 11},
      {State::quick_stop_active, cw::kDisableVoltage, State::switch_on_disabled, 12},
      {State::fault, cw::kFaultResetCommand, State::switch_on_disabled, 15},
  };
  for (const Case& c : cases) {
    StateMachine m = machine_in(c.from);
    ASSERT_EQ(m.state(), c.from);
    EXPECT_TRUE(m.apply_controlword(c.controlword)) << to_string(c.from) << " cw " << c.controlword;
    EXPECT_EQ(m.state(), c.to) << to_string(c.from) << " cw " << c.controlword;
    EXPECT_EQ(m.last_transition(), c.number) << to_string(c.from) << " cw " << c.controlword;
  }
}

TEST(Cia402Transitions, InternalEventsPowerUpFaultAndRampEnd) {
  StateMachine m;
  EXPECT_EQ(m.state(), State::not_ready_to_switch_on);
  EXPECT_TRUE(m.apply(Command::self_test_done));  // 1
  EXPECT_EQ(m.state(), State::switch_on_disabled);
  EXPECT_EQ(m.last_transition(), 1);

  const State every_non_fault_state[] = {State::switch_on_disabled, State::ready_to_switch_on, State::switched_on,
                                         State::operation_enabled, State::quick_stop_active};
  for (State s : every_non_fault_state) {
    StateMachine f = machine_in(s);
    EXPECT_TRUE(f.apply(Command::fault_detected)) << to_string(s);  // 13
    EXPECT_EQ(f.state(), State::fault_reaction_active);
    EXPECT_EQ(f.last_transition(), 13);
    EXPECT_TRUE(f.apply(Command::stopped));  // 14
    EXPECT_EQ(f.state(), State::fault);
    EXPECT_EQ(f.last_transition(), 14);
  }
  StateMachine q = machine_in(State::quick_stop_active);
  EXPECT_TRUE(q.apply(Command::stopped));  // 12 when the ramp ends (quick stop option code 2)
  EXPECT_EQ(q.state(), State::switch_on_disabled);
}

TEST(Cia402Refusals, CommandsThatSkipStatesAreRefused) {
  struct Refused {
    State from;
    std::uint16_t controlword;
  };
  const Refused refused[] = {
      {State::switch_on_disabled, cw::kSwitchOnCommand},            // must shut down first
      {State::switch_on_disabled, cw::kEnableOperationCommand},
      {State::quick_stop_active, cw::kEnableOperationCommand},      // transition 16: option code 2 has none
      {State::quick_stop_active, cw::kShutdown},
      {State::fault, cw::kEnableOperationCommand},                  // only a reset leaves Fault
      {State::fault, cw::kSwitchOnCommand},
  };
  for (const Refused& r : refused) {
    StateMachine m = machine_in(r.from);
    const std::uint32_t before = m.refused_count();
    EXPECT_FALSE(m.apply_controlword(r.controlword)) << to_string(r.from) << " cw " << r.controlword;
    EXPECT_EQ(m.state(), r.from);
    EXPECT_EQ(m.refused_count(), before + 1);
  }
  StateMachine n;  // before the self test: no command is taken
  EXPECT_FALSE(n.apply_controlword(cw::kShutdown));
  EXPECT_EQ(n.state(), State::not_ready_to_switch_on);
}

TEST(Cia402Refusals, FaultResetNeedsARisingEdgeAndAClearedCause) {
  StateMachine m = machine_in(State::fault);
  m.set_fault_reset_allowed(false);
  EXPECT_FALSE(m.apply_controlword(cw::kFaultResetCommand));
  EXPECT_EQ(m.state(), State::fault);
  m.set_fault_reset_allowed(true);
  EXPECT_TRUE(m.apply_controlword(cw::kFaultResetCommand));  // bit 7 still high: no edge, no command
  EXPECT_EQ(m.state(), State::fault);
  EXPECT_TRUE(m.apply_controlword(cw::kDisableVoltage));
  EXPECT_TRUE(m.apply_controlword(cw::kFaultResetCommand));  // rising edge
  EXPECT_EQ(m.state(), State::switch_on_disabled);
  // A reset edge outside Fault does nothing.
  StateMachine e = machine_in(State::operation_enabled);
  EXPECT_FALSE(e.apply_controlword(cw::kFaultResetCommand | cw::kEnableOperationCommand));
  EXPECT_EQ(e.state(), State::operation_enabled);
}

TEST(Cia402Statusword, EachStateShowsTheStandardPattern) {
  struct Pattern {
    State state;
    std::uint16_t statusword;
  };
  // The values real drives report (remote bit 9 set, mains present so voltage enabled).
  const Pattern patterns[] = {
      {State::not_ready_to_switch_on, 0x0200}, {State::switch_on_disabled, 0x0250}, {State::ready_to_switch_on, 0x0231},
      {State::switched_on, 0x0233},            {State::operation_enabled, 0x0237},  {State::quick_stop_active, 0x0217},
      {State::fault_reaction_active, 0x021F},  {State::fault, 0x0218},
  };
  for (const Pattern& p : patterns) {
    EXPECT_EQ(statusword_bits(p.state), p.statusword) << to_string(p.state);
    EXPECT_EQ(state_from_statusword(p.statusword), p.state) << to_string(p.state);
  }
}

TEST(Cia402Controlword, CommandPatternsIgnoreTheDontCareBits) {
  EXPECT_EQ(decode_controlword(0x0006, 0), Command::shutdown);
  EXPECT_EQ(decode_controlword(0x000E, 0), Command::shutdown);  // bit 3 is x
  EXPECT_EQ(decode_controlword(0x0007, 0), Command::switch_on);
  EXPECT_EQ(decode_controlword(0x000F, 0), Command::enable_operation);
  EXPECT_EQ(decode_controlword(0x010F, 0), Command::enable_operation);  // halt bit does not change the command
  EXPECT_EQ(decode_controlword(0x0000, 0), Command::disable_voltage);
  EXPECT_EQ(decode_controlword(0x000D, 0), Command::disable_voltage);  // bit 1 = 0
  EXPECT_EQ(decode_controlword(0x0002, 0), Command::quick_stop);
  EXPECT_EQ(decode_controlword(0x000B, 0), Command::quick_stop);
  EXPECT_EQ(decode_controlword(0x0080, 0x0000), Command::fault_reset);
  EXPECT_EQ(decode_controlword(0x0080, 0x0080), Command::none);
  EXPECT_EQ(decode_controlword(0x0086, 0x0080), Command::none);
}

TEST(Cia402Table, RunsOnTheFsmEngineWithOneRowPerStateAndCommand) {
  EXPECT_EQ(fsm::check_definition<Cia402Definition>(), fsm::DefinitionCheck::ok);
  for (const auto& row : Cia402Definition::kRows) {
    EXPECT_EQ(StateMachine::Machine::find_row(row.from, row.input), &row);
  }
  // Every state can be left (no dead end) and every non-fault state can fault.
  for (const auto& spec : Cia402Definition::kStates) {
    bool leaves = false;
    for (const auto& row : Cia402Definition::kRows) leaves = leaves || (row.from == spec.state && row.to != spec.state);
    EXPECT_TRUE(leaves) << spec.name;
    EXPECT_NE(StateMachine::Machine::find_row(spec.state, Command::fault_detected), nullptr) << spec.name;
  }
}

}  // namespace
}  // namespace rescue::drivers::cia402
