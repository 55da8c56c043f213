// Master::request_register_read (ctl reg_read, docs/master.md "Register reads") on the simulated
// robot in OP: the FPRD goes in the next cyclic frame and its bytes are the slave ESC's own; one
// read at a time, and a length, range or position out of bounds is refused before anything is sent;
// a slave out of the exchange (its cable cut, confirmed lost) is never addressed; a read whose slave
// is cut off while it is under way ends within the service's tries; the cycle never waits.
#include <gtest/gtest.h>

#include "ecat/codec/registers.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

void run(SimulatedRobotRig& rig, int n) { rig.idle_cycles(n); }

TEST(MasterRegisterRead, TheBytesAreTheSlaveEscsOwnAndOneReadIsUnderWayAtATime) {
  auto rig = testing::simulated_robot_in_op();
  Master& master = rig->bus.master();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(master.request_register_read(elbow, reg::kAlStatus, 2));
  EXPECT_FALSE(master.request_register_read(0, reg::kAlStatus, 2)) << "one at a time";
  RegisterReadResult r;
  EXPECT_FALSE(master.take_register_read(r)) << "nothing before a frame";
  run(*rig, 1);
  ASSERT_TRUE(master.take_register_read(r));
  EXPECT_EQ(r.status, RegisterReadStatus::ok);
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.frames, 1);
  EXPECT_EQ(r.data[0], rig->segment.esc(elbow).register_u8(reg::kAlStatus));
  EXPECT_EQ(r.data[0], 0x08) << "OP";
  EXPECT_FALSE(master.take_register_read(r)) << "taken once";

  ASSERT_TRUE(master.request_register_read(0, 0x0000, 64));
  run(*rig, 1);
  ASSERT_TRUE(master.take_register_read(r));
  ASSERT_EQ(r.status, RegisterReadStatus::ok);
  for (std::uint16_t i = 0; i < 64; ++i) EXPECT_EQ(r.data[i], rig->segment.esc(0).register_u8(i)) << i;

  EXPECT_FALSE(master.request_register_read(elbow, 0x0130, 0));
  EXPECT_FALSE(master.request_register_read(elbow, 0x0130, kMaxRegisterReadLength + 1));
  EXPECT_FALSE(master.request_register_read(elbow, 0xFFFF, 2)) << "past the register space";
  EXPECT_FALSE(master.request_register_read(kSlaveCount, 0x0130, 2)) << "no such slave";
}

TEST(MasterRegisterRead, ALostSlaveIsNeverAddressedAndAReadCutOffEndsWithoutWaiting) {
  auto rig = testing::simulated_robot_in_op();
  Master& master = rig->bus.master();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(rig->segment.cut_link(elbow).ok());
  run(*rig, 50);
  ASSERT_NE(master.monitor().out_of_exchange() & slave_bit(elbow), 0U) << "confirmed lost";
  ASSERT_TRUE(master.request_register_read(elbow, reg::kAlStatus, 2));
  run(*rig, 1);
  RegisterReadResult r;
  ASSERT_TRUE(master.take_register_read(r));
  EXPECT_EQ(r.status, RegisterReadStatus::out_of_exchange);
  EXPECT_EQ(r.frames, 0) << "nothing sent";

  const std::size_t neck = slave_position_of_joint(joint_index_by_name("neck_pan"));
  ASSERT_TRUE(master.request_register_read(neck, reg::kAlStatus, 2));
  ASSERT_TRUE(rig->segment.cut_link(neck).ok());  // cut while the read is under way: never answered
  run(*rig, RegisterReadService::kTries);
  ASSERT_TRUE(master.take_register_read(r)) << "ended after its tries";
  if (r.status == RegisterReadStatus::not_answered) {
    EXPECT_EQ(r.frames, RegisterReadService::kTries);
    EXPECT_EQ(r.wkc, 0);
  } else {
    // The link monitor confirmed the loss first: then it was not addressed again.
    EXPECT_EQ(r.status, RegisterReadStatus::out_of_exchange);
    EXPECT_LT(r.frames, RegisterReadService::kTries);
  }
}

}  // namespace
}  // namespace rescue::ecat
