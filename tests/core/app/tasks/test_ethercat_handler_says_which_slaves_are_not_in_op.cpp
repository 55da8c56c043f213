// The EtherCAT handler before OP is never silent (issue 22): on the simulated robot in virtual time,
// with l_elbow's application hung after bring-up (its AL control is not served, so it stays in
// SAFE-OP), the handler posts about once a second which slaves are not in OP yet, with the AL status
// of the first, and the master keeps asking past its OP timeout; once the application runs again the
// network reaches OP and the events stop.
#include <gtest/gtest.h>

#include "core/app/tasks/ethercat_handler.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"

namespace rescue::app {
namespace {

TEST(EthercatHandlerBeforeOp, SaysEverySecondWhichSlavesAreNotInOpAndKeepsTrying) {
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  ASSERT_TRUE(fw.rig->built.ok());
  ecat::MasterOptions options = rescue::testing::fast_options();
  ASSERT_TRUE(fw.bring_up(options)) << rescue::testing::describe_master_failure(fw.rig->bus.master());
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(fw.rig->segment.freeze(elbow, true).ok());
  int waiting = 0;
  HandlerEvent last{};
  for (int i = 0; i < 7000; ++i) {
    EXPECT_NE(fw.period().state, ecat::MasterState::op);
    HandlerEvent e{};
    while (fw.handler->pop_event(e)) {
      if (e.kind != HandlerEventKind::waiting_for_op) continue;
      ++waiting;
      last = e;
    }
  }
  // 7 s past SAFE-OP: 6 or 7 events, beyond the master's 3 s OP timeout.
  EXPECT_GE(waiting, 6);
  EXPECT_LE(waiting, 7);
  EXPECT_EQ(last.link.slaves, ecat::slave_bit(elbow)) << "only l_elbow is not in OP";
  EXPECT_EQ(last.joints, joint_bit(joint_index_by_name("l_elbow")));
  EXPECT_EQ(last.link.al_status & ecat::reg::kAlStateMask, static_cast<std::uint16_t>(ecat::reg::AlState::safe_op));
  EXPECT_GE(last.link.time, 6 * hal::kNsPerSec);
  EXPECT_STREQ(fw.rig->bus.master().report().failed_step, "OP") << "the timeout is reported";
  // Its application runs again: the master, still asking, gets it to OP.
  ASSERT_TRUE(fw.rig->segment.freeze(elbow, false).ok());
  bool op = false;
  for (int i = 0; i < 5000 && !op; ++i) {
    op = fw.period().state == ecat::MasterState::op;
    HandlerEvent e{};
    while (fw.handler->pop_event(e)) {
    }
  }
  EXPECT_TRUE(op);
  int after = 0;
  for (int i = 0; i < 2000; ++i) {
    (void)fw.period();
    HandlerEvent e{};
    while (fw.handler->pop_event(e)) after += e.kind == HandlerEventKind::waiting_for_op ? 1 : 0;
  }
  EXPECT_EQ(after, 0);
}

}  // namespace
}  // namespace rescue::app
