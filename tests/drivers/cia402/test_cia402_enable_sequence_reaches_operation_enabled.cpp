// The master's CiA 402 helper driving the drive-side state machine (drivers/cia402/cia402.hpp): from
// every state it reaches Operation enabled in a few cycles, a fault is reset by a rising edge of
// bit 7 (also when bit 7 was already high), and the disable helper brings the drive to a stop.
#include <gtest/gtest.h>

#include "drivers/cia402/cia402.hpp"
#include "drivers/cia402/cia402_enable.hpp"

namespace rescue::drivers {
namespace {

using cia402::State;

// Runs the helper against the state machine until Operation enabled; returns the cycles taken.
int cycles_to_enable(cia402::StateMachine& sm, std::uint16_t previous) {
  for (int cycle = 1; cycle <= 10; ++cycle) {
    const std::uint16_t statusword = cia402::statusword_bits(sm.state());
    if (is_enabled(statusword)) return cycle - 1;
    previous = controlword_towards_enabled(statusword, previous);
    (void)sm.apply_controlword(previous);
  }
  return -1;
}

TEST(Cia402Enable, FromSwitchOnDisabledInThreeCycles) {
  cia402::StateMachine sm;
  ASSERT_TRUE(sm.apply(cia402::Command::self_test_done));
  EXPECT_EQ(cycles_to_enable(sm, 0), 3);
  EXPECT_EQ(sm.refused_count(), 0u);
}

TEST(Cia402Enable, FromFaultThroughAResetEdge) {
  cia402::StateMachine sm;
  ASSERT_TRUE(sm.apply(cia402::Command::self_test_done));
  ASSERT_TRUE(sm.apply(cia402::Command::fault_detected));
  ASSERT_TRUE(sm.apply(cia402::Command::stopped));
  ASSERT_EQ(sm.state(), State::fault);
  EXPECT_TRUE(is_faulted(cia402::statusword_bits(sm.state())));
  EXPECT_EQ(cycles_to_enable(sm, 0), 4);  // reset, shutdown, switch on, enable
}

TEST(Cia402Enable, FaultResetWhenBit7WasAlreadyHigh) {
  cia402::StateMachine sm;
  ASSERT_TRUE(sm.apply(cia402::Command::self_test_done));
  (void)sm.apply_controlword(0x0080);  // bit 7 high before the fault: no edge left to give
  ASSERT_TRUE(sm.apply(cia402::Command::fault_detected));
  ASSERT_TRUE(sm.apply(cia402::Command::stopped));
  EXPECT_EQ(controlword_towards_enabled(cia402::statusword_bits(State::fault), 0x0080), 0x0000);
  EXPECT_EQ(cycles_to_enable(sm, 0x0080), 5);
}

TEST(Cia402Enable, FromQuickStopBackToEnabled) {
  cia402::StateMachine sm;
  ASSERT_TRUE(sm.apply(cia402::Command::self_test_done));
  ASSERT_EQ(cycles_to_enable(sm, 0), 3);
  (void)sm.apply_controlword(cia402::cw::kQuickStopCommand);
  ASSERT_EQ(sm.state(), State::quick_stop_active);
  EXPECT_GE(cycles_to_enable(sm, cia402::cw::kQuickStopCommand), 3);
  EXPECT_EQ(sm.state(), State::operation_enabled);
}

TEST(Cia402Enable, DisableStopsThroughDisableOperation) {
  cia402::StateMachine sm;
  ASSERT_TRUE(sm.apply(cia402::Command::self_test_done));
  ASSERT_EQ(cycles_to_enable(sm, 0), 3);
  for (int i = 0; i < 3; ++i) (void)sm.apply_controlword(controlword_towards_disabled(cia402::statusword_bits(sm.state())));
  EXPECT_EQ(sm.state(), State::switch_on_disabled);
}

}  // namespace
}  // namespace rescue::drivers
