// Master::request_slave_state (ctl states, docs/master.md "AL states on request") on the simulated
// robot in OP with online recovery: a drive asked for PRE-OP reaches it through AL control writes in
// the cyclic frame (its ESC says PRE-OP), is taken out of the exchange by the link monitor and stays
// parked there: the online recovery never takes it back behind the operator's back; asked for OP it
// is handed back to the recovery and returns to the exchange in OP. One request at a time; a state
// that cannot be asked for, no slave, or a slave the recovery is configuring are refused before
// anything is written; a state the slave refuses ends refused with its AL status code after an
// acknowledge and a plain request; a slave cut off ends not_answered at the deadline; the cycle never waits.
#include <gtest/gtest.h>

#include "ecat/codec/registers.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;
using Refusal = SlaveStateService::Refusal;

MasterOptions recovery_options() {
  MasterOptions options = testing::fast_options();
  options.online_recovery = true;
  return options;
}

// Cycles until the request's result comes (at most `limit` periods); false if it did not.
bool run_until_done(SimulatedRobotRig& rig, SlaveStateResult& out, int limit) {
  for (int i = 0; i < limit; ++i) {
    rig.idle_cycles(1);
    if (rig.bus.master().take_slave_state(out)) return true;
  }
  return false;
}

std::uint8_t esc_al_state(SimulatedRobotRig& rig, std::size_t position) {
  return rig.segment.esc(position).register_u8(reg::kAlStatus) & reg::kAlStateMask;
}

TEST(MasterSlaveStates, ADriveParkedAtPreOpStaysThereUntilAskedForOpThenRecoveryBringsItBack) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  Master& master = rig->bus.master();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  const SlaveMask bit = slave_bit(elbow);
  ASSERT_EQ(master.request_slave_state(bit, reg::AlState::pre_op), Refusal::none);
  EXPECT_EQ(master.request_slave_state(slave_bit(0), reg::AlState::init), Refusal::busy) << "one at a time";
  SlaveStateResult r;
  EXPECT_FALSE(master.take_slave_state(r)) << "nothing before a frame";
  ASSERT_TRUE(run_until_done(*rig, r, 100));
  EXPECT_EQ(r.slaves, bit);
  EXPECT_EQ(r.outcome[elbow], SlaveStateOutcome::reached);
  EXPECT_EQ(r.al_status[elbow], static_cast<std::uint16_t>(reg::AlState::pre_op));
  EXPECT_EQ(esc_al_state(*rig, elbow), static_cast<std::uint8_t>(reg::AlState::pre_op));
  EXPECT_EQ(master.parked(), bit);
  EXPECT_FALSE(master.take_slave_state(r)) << "taken once";

  // Two seconds on: out of the exchange, and the online recovery (1 s steps and hold-offs) left it alone.
  rig->idle_cycles(2000);
  EXPECT_NE(master.monitor().out_of_exchange() & bit, 0U);
  EXPECT_EQ(master.recovery_state(elbow), RecoveryState::idle);
  EXPECT_EQ(esc_al_state(*rig, elbow), static_cast<std::uint8_t>(reg::AlState::pre_op));
  EXPECT_EQ(master.recovery_stats().recovered, 0U);

  ASSERT_EQ(master.request_slave_state(bit, reg::AlState::op), Refusal::none);
  EXPECT_EQ(master.parked(), 0U) << "handed back to the online recovery";
  ASSERT_TRUE(run_until_done(*rig, r, 2000));
  EXPECT_EQ(r.outcome[elbow], SlaveStateOutcome::reached);
  EXPECT_NE(master.monitor().in_exchange() & bit, 0U);
  EXPECT_EQ(esc_al_state(*rig, elbow), static_cast<std::uint8_t>(reg::AlState::op));
  EXPECT_EQ(master.recovery_stats().recovered, 1U);
}

TEST(MasterSlaveStates, BadRequestsAreRefusedBeforeAnythingIsWrittenAndACutSlaveIsNotAnswered) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  Master& master = rig->bus.master();
  EXPECT_EQ(master.request_slave_state(0, reg::AlState::init), Refusal::bad_request) << "no slave";
  EXPECT_EQ(master.request_slave_state(slave_bit(3), reg::AlState::boot), Refusal::bad_request);
  EXPECT_EQ(master.request_slave_state(slave_bit(kMaxSlaves - 1) << 1, reg::AlState::init), Refusal::bad_request);
  EXPECT_EQ(master.parked(), 0U);

  const std::size_t neck = slave_position_of_joint(joint_index_by_name("neck_tilt"));
  ASSERT_TRUE(rig->segment.cut_link(neck).ok());
  rig->idle_cycles(50);
  ASSERT_NE(master.monitor().out_of_exchange() & slave_bit(neck), 0U) << "confirmed lost";
  // Lost: the online recovery searches for it (no step under way: it may be parked).
  ASSERT_EQ(master.request_slave_state(slave_bit(neck), reg::AlState::init), Refusal::none);
  SlaveStateResult r;
  const int limit = static_cast<int>(SlaveStateService::kDeadline / hal::kNsPerMs) + 100;
  ASSERT_TRUE(run_until_done(*rig, r, limit)) << "ends at its deadline";
  EXPECT_EQ(r.outcome[neck], SlaveStateOutcome::not_answered);
  EXPECT_EQ(r.al_status[neck], 0U);
  EXPECT_EQ(master.parked(), slave_bit(neck));
  EXPECT_EQ(master.recovery_state(neck), RecoveryState::idle) << "parked: not searched for";

  // The cable back: still parked, so not recovered behind the operator's back.
  ASSERT_TRUE(rig->segment.restore_link(neck).ok());
  rig->idle_cycles(1500);
  EXPECT_EQ(master.recovery_state(neck), RecoveryState::idle);
  EXPECT_NE(master.monitor().out_of_exchange() & slave_bit(neck), 0U);
}

TEST(MasterSlaveStates, AStateTheSlaveRefusesIsAnsweredWithItsAlStatusCode) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  Master& master = rig->bus.master();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  ASSERT_EQ(master.request_slave_state(slave_bit(elbow), reg::AlState::init), Refusal::none);
  SlaveStateResult r;
  ASSERT_TRUE(run_until_done(*rig, r, 100));
  EXPECT_EQ(r.outcome[elbow], SlaveStateOutcome::reached);
  EXPECT_EQ(esc_al_state(*rig, elbow), static_cast<std::uint8_t>(reg::AlState::init));
  // INIT -> SAFE-OP skips PRE-OP: the ESC refuses it (0x0011), acknowledged and asked again, refused again.
  ASSERT_EQ(master.request_slave_state(slave_bit(elbow), reg::AlState::safe_op), Refusal::none);
  ASSERT_TRUE(run_until_done(*rig, r, 100));
  EXPECT_EQ(r.outcome[elbow], SlaveStateOutcome::refused);
  EXPECT_NE(r.al_status[elbow] & reg::kAlErrorBit, 0U);
  EXPECT_EQ(r.al_code[elbow], reg::al_code::kInvalidStateChange);
  EXPECT_EQ(master.parked(), slave_bit(elbow)) << "still parked, at the state it holds";
}

TEST(MasterSlaveStates, ASlaveTheRecoveryIsConfiguringIsRefused) {
  auto rig = testing::simulated_robot_in_op(recovery_options());
  Master& master = rig->bus.master();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(rig->segment.power_cycle(elbow, rig->clock.now()).ok());
  // Until the recovery takes a step on it (it was found again after its power cycle).
  bool configuring = false;
  for (int i = 0; i < 3000 && !configuring; ++i) {
    rig->idle_cycles(1);
    const RecoveryState s = master.recovery_state(elbow);
    configuring = s != RecoveryState::idle && s != RecoveryState::searching && s != RecoveryState::failed &&
                  s != RecoveryState::refused;
  }
  ASSERT_TRUE(configuring);
  EXPECT_EQ(master.request_slave_state(slave_bit(elbow), reg::AlState::pre_op), Refusal::recovering);
  EXPECT_EQ(master.parked(), 0U);
}

}  // namespace
}  // namespace rescue::ecat
