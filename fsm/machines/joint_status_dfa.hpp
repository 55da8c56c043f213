// The joint status DFA of the design brief, section 5 (the paper's Fig. 3): five states, seven inputs,
// one table. Every (state, input) pair missing from kRows is refused and counted by the engine.
//
// The context carries the facts the reset guard reads (kept current by the joint manager) and the
// effects the actions produce (mode, reference, drive enable), which the joint manager publishes to
// the EtherCAT handler. The DFA itself never touches shared memory or the network.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/robot/robot.hpp"
#include "fsm/engine/engine.hpp"

namespace rescue::fsm {

enum class JointState : std::uint8_t { idle = 0, configured = 1, ready = 2, enabled = 3, error = 4 };
enum class JointInput : std::uint8_t {
  select_mode = 0,
  set_reference = 1,
  enable = 2,
  disable = 3,
  fault = 4,
  comm_lost = 5,
  reset = 6,
};

constexpr std::size_t kJointStateCount = 5;
constexpr std::size_t kJointInputCount = 7;

struct JointContext {
  // Facts the guards read; the joint manager keeps them current before dispatching.
  bool reachable{true};      // the EtherCAT handler reaches the joint's slave
  bool fault_present{false}; // the drive reports a fault or a limit is violated right now
  bool loss_latched{false};  // recorded as lost (comm_lost or the error-joints file) until an operator clears it
  ControlMode requested_mode{ControlMode::none};  // argument of select_mode
  double actual_position_rad{0.0};                // argument of set_reference: the current position

  // Effects the actions write; the joint manager publishes them to the EtherCAT handler.
  ControlMode mode{ControlMode::none};
  double reference_position_rad{0.0};
  bool drive_enabled{false};  // false: drive disabled, the worm gear holds the joint
};

// The one guard of the table: reset leaves Error only for a reachable joint whose fault is cleared.
constexpr bool joint_may_reset(const JointContext& c) noexcept {
  return c.reachable && !c.fault_present && !c.loss_latched;
}

struct JointStatusDfa {
  using State = JointState;
  using Input = JointInput;
  using Context = JointContext;
  using S = JointState;
  using I = JointInput;

  static constexpr const char* kName = "joint_status";
  static constexpr State kInitial = S::idle;

  static constexpr Guard<Context> kMayReset{&joint_may_reset,
                                            "only if the joint is reachable and its fault cleared"};
  static constexpr Action<Context> kApplyMode{
      [](Context& c) noexcept { c.mode = c.requested_mode; }, "mode := requested mode"};
  static constexpr Action<Context> kAlignReference{
      [](Context& c) noexcept { c.reference_position_rad = c.actual_position_rad; },
      "reference := actual position"};
  static constexpr Action<Context> kClearMode{[](Context& c) noexcept { c.mode = ControlMode::none; },
                                              "mode := none"};
  static constexpr Action<Context> kEnableDrive{[](Context& c) noexcept { c.drive_enabled = true; },
                                                "drive enabled"};
  static constexpr Action<Context> kDisableDrive{[](Context& c) noexcept { c.drive_enabled = false; },
                                                 "drive disabled (worm gear holds)"};

  // clang-format off
  static constexpr std::array<StateSpec<State, Context>, kJointStateCount> kStates{{
    {S::idle,       "Idle",       "reachable, drive disabled, no control mode", kClearMode, {}},
    {S::configured, "Configured", "control mode chosen (position, velocity or torque)", {}, {}},
    {S::ready,      "Ready",      "reference aligned with the current position, so enabling moves nothing", {}, {}},
    {S::enabled,    "Enabled",    "drive enabled, following references", kEnableDrive, kDisableDrive},
    {S::error,      "Error",      "limit violation, drive fault or lost communication; drive disabled", kDisableDrive, {}},
  }};
  static constexpr std::array<InputSpec<Input>, kJointInputCount> kInputs{{
    {I::select_mode,   "select_mode",   "choose the control mode (CSP, CSV, CST)"},
    {I::set_reference, "set_reference", "set the reference to the current position"},
    {I::enable,        "enable",        "enable the drive"},
    {I::disable,       "disable",       "disable the drive (Enabled) or step back (Ready, Configured)"},
    {I::fault,         "fault",         "limit violation or drive fault"},
    {I::comm_lost,     "comm_lost",     "the EtherCAT handler lost the joint (reconfiguration)"},
    {I::reset,         "reset",         "operator reset after the fault is cleared"},
  }};
  static constexpr std::array<Row<State, Input, Context>, 20> kRows{{
    {S::idle,       I::select_mode,   S::configured, {}, kApplyMode},
    {S::idle,       I::fault,         S::error,      {}, {}},
    {S::idle,       I::comm_lost,     S::error,      {}, {}},
    {S::configured, I::select_mode,   S::configured, {}, kApplyMode},
    {S::configured, I::set_reference, S::ready,      {}, kAlignReference},
    {S::configured, I::disable,       S::idle,       {}, {}},
    {S::configured, I::fault,         S::error,      {}, {}},
    {S::configured, I::comm_lost,     S::error,      {}, {}},
    {S::ready,      I::select_mode,   S::configured, {}, kApplyMode},
    {S::ready,      I::set_reference, S::ready,      {}, kAlignReference},
    {S::ready,      I::enable,        S::enabled,    {}, kAlignReference},
    {S::ready,      I::disable,       S::idle,       {}, {}},
    {S::ready,      I::fault,         S::error,      {}, {}},
    {S::ready,      I::comm_lost,     S::error,      {}, {}},
    {S::enabled,    I::disable,       S::ready,      {}, kAlignReference},
    {S::enabled,    I::fault,         S::error,      {}, {}},
    {S::enabled,    I::comm_lost,     S::error,      {}, {}},
    {S::error,      I::fault,         S::error,      {}, {}},
    {S::error,      I::comm_lost,     S::error,      {}, {}},
    {S::error,      I::reset,         S::idle,       kMayReset, {}},
  }};
  // clang-format on
};

using JointStatusMachine = Machine<JointStatusDfa>;

const char* to_string(JointState state) noexcept;
const char* to_string(JointInput input) noexcept;
// Parses an input name ("select_mode", ...); false when unknown.
bool parse_joint_input(const char* name, JointInput& out) noexcept;

// The robot-level summary, derived from the 21 joint states alone.
enum class RobotCondition : std::uint8_t {
  idle,        // every joint Idle
  configured,  // no joint in Error, the least advanced is Configured
  ready,       // no joint in Error, the least advanced is Ready
  enabled,     // every joint Enabled
  degraded,    // some joints in Error, the others usable (the reconfigured robot)
  error,       // every joint in Error
};

const char* to_string(RobotCondition condition) noexcept;

struct RobotStatusSummary {
  std::array<JointMask, kJointStateCount> joints_in{};  // by state index
  JointMask usable{0};                                  // joints not in Error
  RobotCondition condition{RobotCondition::idle};
};

RobotStatusSummary summarize(const std::array<JointState, kJointCount>& states) noexcept;

}  // namespace rescue::fsm
