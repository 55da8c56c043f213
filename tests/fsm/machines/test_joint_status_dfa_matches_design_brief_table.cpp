// Every (state, input) pair of the joint status DFA against the design brief's table (section 5),
// written out here independently of fsm/machines/joint_status_dfa.hpp, plus the reset guard, the actions and
// the robot-level summary.
#include <gtest/gtest.h>

#include <string>

#include "fsm/machines/joint_status_dfa.hpp"

namespace rescue::fsm {
namespace {

using S = JointState;
using I = JointInput;

// The brief's table, row by row; "-" = not in the table (refused and counted).
// clang-format off
const char* const kBriefTable[kJointStateCount][kJointInputCount] = {
  //               select_mode    set_reference enable     disable   fault    comm_lost reset
  /* Idle       */ {"Configured", "-",          "-",       "-",      "Error", "Error",  "-"},
  /* Configured */ {"Configured", "Ready",      "-",       "Idle",   "Error", "Error",  "-"},
  /* Ready      */ {"Configured", "Ready",      "Enabled", "Idle",   "Error", "Error",  "-"},
  /* Enabled    */ {"-",          "-",          "-",       "Ready",  "Error", "Error",  "-"},
  /* Error      */ {"-",          "-",          "-",       "-",      "Error", "Error",  "Idle"},
};
// clang-format on

// Drives a fresh machine into `target` along legal transitions.
JointStatusMachine machine_in(S target, JointContext& ctx) {
  JointStatusMachine m;
  auto go = [&](I input) { EXPECT_TRUE(m.dispatch(ctx, input).ok()); };
  switch (target) {
    case S::idle: break;
    case S::configured: go(I::select_mode); break;
    case S::ready: go(I::select_mode); go(I::set_reference); break;
    case S::enabled: go(I::select_mode); go(I::set_reference); go(I::enable); break;
    case S::error: go(I::fault); break;
  }
  EXPECT_EQ(m.state(), target);
  return m;
}

class JointDfaPair : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(JointDfaPair, FollowsTheBriefTable) {
  const auto from = static_cast<S>(std::get<0>(GetParam()));
  const auto input = static_cast<I>(std::get<1>(GetParam()));
  JointContext ctx;  // reachable, no fault, not latched: the reset guard passes
  ctx.requested_mode = ControlMode::cyclic_position;
  JointStatusMachine m = machine_in(from, ctx);
  const std::uint32_t accepted = m.accepted_count();
  const std::string expected = kBriefTable[std::get<0>(GetParam())][std::get<1>(GetParam())];

  const Status status = m.dispatch(ctx, input);
  if (expected == "-") {
    ASSERT_FALSE(status.ok()) << to_string(from) << " + " << to_string(input) << " must be refused";
    EXPECT_EQ(status.error().code, Errc::refused);
    EXPECT_STREQ(status.error().what, kRefusedNotInTable);
    EXPECT_EQ(m.state(), from);
    EXPECT_EQ(m.refused_count(), 1u);
    EXPECT_EQ(m.accepted_count(), accepted);
  } else {
    ASSERT_TRUE(status.ok()) << to_string(from) << " + " << to_string(input) << ": " << status.error().what;
    EXPECT_STREQ(to_string(m.state()), expected.c_str());
    EXPECT_EQ(m.refused_count(), 0u);
  }
}

std::string pair_name(const ::testing::TestParamInfo<std::tuple<int, int>>& info) {
  return std::string(to_string(static_cast<S>(std::get<0>(info.param)))) + "_" +
         to_string(static_cast<I>(std::get<1>(info.param)));
}

INSTANTIATE_TEST_SUITE_P(All35Pairs, JointDfaPair,
                         ::testing::Combine(::testing::Range(0, static_cast<int>(kJointStateCount)),
                                            ::testing::Range(0, static_cast<int>(kJointInputCount))),
                         pair_name);

TEST(JointDfa, TableListsExactlyTheBriefsTwentyTransitions) {
  int listed = 0;
  for (const auto& row : kBriefTable) {
    for (const char* cell : row) listed += std::string(cell) != "-" ? 1 : 0;
  }
  EXPECT_EQ(listed, 20);
  EXPECT_EQ(JointStatusDfa::kRows.size(), 20u);
}

TEST(JointDfa, ResetNeedsReachableJointWithFaultCleared) {
  struct Case {
    bool reachable, fault_present, loss_latched, allowed;
  };
  for (const Case c : {Case{true, false, false, true}, Case{false, false, false, false},
                       Case{true, true, false, false}, Case{true, false, true, false},
                       Case{false, true, true, false}}) {
    JointContext ctx;
    JointStatusMachine m = machine_in(S::error, ctx);
    ctx.reachable = c.reachable;
    ctx.fault_present = c.fault_present;
    ctx.loss_latched = c.loss_latched;
    const Status s = m.dispatch(ctx, I::reset);
    EXPECT_EQ(s.ok(), c.allowed) << c.reachable << c.fault_present << c.loss_latched;
    EXPECT_EQ(m.state(), c.allowed ? S::idle : S::error);
    if (!c.allowed) {
      EXPECT_STREQ(s.error().what, kRefusedByGuard);
      EXPECT_EQ(m.last_refusal().why, Refusal::guard_failed);
    }
  }
}

TEST(JointDfa, SelectModeAppliesTheRequestedModeAndIdleClearsIt) {
  JointContext ctx;
  JointStatusMachine m;
  ctx.requested_mode = ControlMode::cyclic_velocity;
  ASSERT_TRUE(m.dispatch(ctx, I::select_mode).ok());
  EXPECT_EQ(ctx.mode, ControlMode::cyclic_velocity);
  ASSERT_TRUE(m.dispatch(ctx, I::disable).ok());
  EXPECT_EQ(ctx.mode, ControlMode::none);
}

TEST(JointDfa, SetReferenceAlignsReferenceWithActualPosition) {
  JointContext ctx;
  JointStatusMachine m = machine_in(S::configured, ctx);
  ctx.actual_position_rad = 1.23456;
  ctx.reference_position_rad = -0.5;
  ASSERT_TRUE(m.dispatch(ctx, I::set_reference).ok());
  EXPECT_EQ(ctx.reference_position_rad, 1.23456);
}

TEST(JointDfa, DriveIsEnabledOnlyInEnabled) {
  JointContext ctx;
  JointStatusMachine m = machine_in(S::ready, ctx);
  EXPECT_FALSE(ctx.drive_enabled);
  ASSERT_TRUE(m.dispatch(ctx, I::enable).ok());
  EXPECT_TRUE(ctx.drive_enabled);
  ASSERT_TRUE(m.dispatch(ctx, I::disable).ok());
  EXPECT_FALSE(ctx.drive_enabled);
  ASSERT_TRUE(m.dispatch(ctx, I::enable).ok());
  ASSERT_TRUE(m.dispatch(ctx, I::comm_lost).ok());
  EXPECT_EQ(m.state(), S::error);
  EXPECT_FALSE(ctx.drive_enabled);
}

TEST(JointDfa, EveryGuardAndActionIsDocumentedAndEveryTextHasAFunction) {
  for (const auto& row : JointStatusDfa::kRows) {
    EXPECT_EQ(row.guard.fn != nullptr, row.guard.text[0] != '\0');
    EXPECT_EQ(row.action.fn != nullptr, row.action.text[0] != '\0');
  }
  for (const auto& state : JointStatusDfa::kStates) {
    EXPECT_EQ(state.on_entry.fn != nullptr, state.on_entry.text[0] != '\0') << state.name;
    EXPECT_EQ(state.on_exit.fn != nullptr, state.on_exit.text[0] != '\0') << state.name;
  }
}

TEST(JointDfa, InputNamesParse) {
  JointInput in = I::fault;
  EXPECT_TRUE(parse_joint_input("set_reference", in));
  EXPECT_EQ(in, I::set_reference);
  EXPECT_FALSE(parse_joint_input("jump", in));
  EXPECT_FALSE(parse_joint_input(nullptr, in));
}

std::array<JointState, kJointCount> all(S s) {
  std::array<JointState, kJointCount> states{};
  states.fill(s);
  return states;
}

TEST(RobotSummary, DerivesConditionFromTheJoints) {
  EXPECT_EQ(summarize(all(S::idle)).condition, RobotCondition::idle);
  EXPECT_EQ(summarize(all(S::enabled)).condition, RobotCondition::enabled);
  EXPECT_EQ(summarize(all(S::ready)).condition, RobotCondition::ready);
  EXPECT_EQ(summarize(all(S::error)).condition, RobotCondition::error);

  auto states = all(S::enabled);
  states[3] = S::ready;
  EXPECT_EQ(summarize(states).condition, RobotCondition::ready);
  states[4] = S::idle;
  EXPECT_EQ(summarize(states).condition, RobotCondition::configured);

  states = all(S::enabled);
  const JointMask lost = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if (lost & joint_bit(j)) states[j] = S::error;
  }
  const RobotStatusSummary summary = summarize(states);
  EXPECT_EQ(summary.condition, RobotCondition::degraded);
  EXPECT_EQ(summary.joints_in[index_of(S::error)], lost);
  EXPECT_EQ(summary.usable, kAllJoints & ~lost);
  EXPECT_EQ(summary.joints_in[index_of(S::enabled)], kAllJoints & ~lost);
  EXPECT_STREQ(to_string(summary.condition), "degraded");
}

}  // namespace
}  // namespace rescue::fsm
