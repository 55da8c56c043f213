// The EtherCAT handler's figures for the operator (EthercatHandler::publish_figures, called by its
// loop after every cycle), with the real handler, master and joint manager on the simulated robot in
// virtual time, wired by TaskPorts as `run` wires them: the master's counters (ctl master) every
// period through EthercatHandlerPorts::master_status, each slave's identity and AL status (ctl
// slaves -v) through slave_info, the link-quality table (ctl diag) through link_diag once a sweep
// completed, and a ctl diag --reset taken from diag_reset, applied, published and marked done; all
// of it (and the joint manager's steps) with the heap guard counting 0 allocations.
#include <gtest/gtest.h>

#include <memory>

#include "core/app/tasks/ethercat_handler.hpp"
#include "core/memory/heap_guard.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::app {
namespace {

constexpr std::uint64_t kLatePeriods = 7;  // what the loop counted: published as given

class HandlerFigures : public ::testing::Test {
 protected:
  void SetUp() override {
    fw = std::make_unique<SimulatedFirmware>(dir.path);
    ASSERT_TRUE(fw->rig->built.ok());
    ASSERT_TRUE(fw->bring_up(rescue::testing::fast_options()))
        << rescue::testing::describe_master_failure(fw->rig->bus.master());
  }
  // One period as the handler's loop runs it: the cycle, then its figures.
  drivers::JointCycleResult period() {
    const drivers::JointCycleResult r = fw->period();
    fw->handler->publish_figures(r, fw->rig->clock.now(), kLatePeriods);
    return r;
  }
  drivers::JointCycleResult until_op() {
    drivers::JointCycleResult r{};
    for (int i = 0; i < 3000 && r.state != ecat::MasterState::op; ++i) r = period();
    return r;
  }

  testing::TempStateDir dir;
  std::unique_ptr<SimulatedFirmware> fw;
};

TEST_F(HandlerFigures, TheMastersCountersAndEachSlavesIdentityArePublishedThroughTheHandlersPorts) {
  const drivers::JointCycleResult r = until_op();
  ASSERT_EQ(r.state, ecat::MasterState::op);
  MasterStatus master{};
  ASSERT_TRUE(fw->links->master_status.try_read(master));
  EXPECT_EQ(master.state, static_cast<std::uint8_t>(ecat::MasterState::op));
  EXPECT_EQ(master.cycles, r.cycle);
  EXPECT_EQ(master.frames_sent, r.cycle);
  EXPECT_EQ(master.frames_lost, fw->handler->frames_missing());
  EXPECT_EQ(master.late_periods, kLatePeriods);
  EXPECT_EQ(master.in_exchange, fw->rig->bus.master().monitor().in_exchange());
  EXPECT_NE(master.in_exchange, 0U);
  EXPECT_EQ(master.lost, 0U);

  protocol::SlaveInfoTable info{};
  ASSERT_TRUE(fw->links->slave_info.try_read(info));
  EXPECT_NE(info.cycle, 0U);
  ASSERT_EQ(info.count, drivers::kRobotNetworkPlan.size());
  for (std::size_t p = 0; p < drivers::kRobotNetworkPlan.size(); ++p) {
    EXPECT_EQ(info.slaves[p].position, p);
    EXPECT_EQ(info.slaves[p].station, drivers::kRobotNetworkPlan[p].station_address);
    EXPECT_NE(info.slaves[p].flags & protocol::kSlaveInfoIdentity, 0) << "slave " << p;
  }
}

TEST_F(HandlerFigures, TheLinkTableIsPublishedPerSweepAndADiagResetIsTakenAppliedAndMarkedDone) {
  ASSERT_EQ(until_op().state, ecat::MasterState::op);
  protocol::DiagPayload diag{};
  for (int i = 0; i < 2000 && diag.sweeps == 0; ++i) {
    (void)period();
    (void)fw->links->link_diag.try_read(diag);
  }
  ASSERT_GE(diag.sweeps, 1U) << "a sweep completed and was published";
  EXPECT_EQ(diag.count, drivers::kRobotNetworkPlan.size());

  // ctl diag --reset of every slave, generation 1, as the socket handler posts it.
  fw->links->diag_reset.requested.store((std::uint64_t{1} << 32) | DiagResetLink::kMaskBits);
  const drivers::JointCycleResult r = period();
  EXPECT_EQ(fw->links->diag_reset.done.load(), 1U);
  ASSERT_TRUE(fw->links->link_diag.try_read(diag));
  EXPECT_EQ(diag.cycle, r.cycle) << "the zeroed table is published in the period that took the reset";
}

TEST_F(HandlerFigures, PublishingTheFiguresAllocatesNothing) {
  ASSERT_EQ(until_op().state, ecat::MasterState::op);
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::count);
  fw->links->diag_reset.requested.store((std::uint64_t{1} << 32) | 0x3U);
  for (int i = 0; i < 500; ++i) (void)period();
  const HeapGuardCounters heap = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(heap.allocations, 0U) << "the handler's figures and the joint manager's status allocate nothing";
  EXPECT_EQ(fw->links->diag_reset.done.load(), 1U);
}

}  // namespace
}  // namespace rescue::app
