// The AL state machine: valid transitions carried out, invalid ones refused with the error
// indication and the AL status code a slave stack gives (0x0011, 0x0012, 0x0013, 0x0016, 0x0017,
// 0x001D, 0x001E, device codes), error acknowledge, SAFE-OP -> OP waiting for valid outputs, the
// process-data watchdog, and device emulation on the junctions.
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr std::uint16_t kStation = 0x1000;

class AlStateMachine : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = Rig::single();
    rig->assign_station_addresses();
  }
  std::uint16_t status() { return rig->read16(kStation, reg::kAlStatus); }
  std::uint16_t status_code() { return rig->read16(kStation, reg::kAlStatusCode); }
  void to_pre_op() {
    configure_mailbox(*rig, kStation);
    ASSERT_EQ(request_state(*rig, kStation, AlState::pre_op), 0x0002);
  }
  void to_safe_op() {
    to_pre_op();
    configure_process_data(*rig, kStation, 0x1000);
    ASSERT_EQ(request_state(*rig, kStation, AlState::safe_op), 0x0004);
  }
  void send_outputs() { EXPECT_EQ(rig->exchange(Command::LRW, 0x1000, std::vector<std::uint8_t>(14, 1)).wkc, 3); }
  std::unique_ptr<Rig> rig;
};

TEST_F(AlStateMachine, PowersUpInInitWithoutError) {
  EXPECT_EQ(status(), 0x0001);
  EXPECT_EQ(status_code(), 0x0000);
  EXPECT_EQ(rig->read16(kStation, reg::kAlControl), 0x0001);
}

TEST_F(AlStateMachine, PreOpWithoutMailboxSyncManagersIsRefusedWith0x0016) {
  EXPECT_EQ(request_state(*rig, kStation, AlState::pre_op), 0x0011);  // INIT + error indication
  EXPECT_EQ(status_code(), 0x0016);
  EXPECT_TRUE(rig->device().transitions.empty());  // refused before the application was asked
}

TEST_F(AlStateMachine, MailboxOfTheWrongDirectionOrSizeIsRefused) {
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(0), sm_config(kMailboxOut, kMailboxSize, kMailboxReadControl, 1)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(1), sm_config(kMailboxIn, kMailboxSize, kMailboxReadControl, 1)).wkc, 1);
  EXPECT_EQ(request_state(*rig, kStation, AlState::pre_op), 0x0011);
  EXPECT_EQ(status_code(), 0x0016);
  // Overlapping mailboxes.
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(0), sm_config(kMailboxOut, kMailboxSize, kMailboxWriteControl, 0)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(1), sm_config(0, 0, 0, 0)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(0), sm_config(kMailboxOut, kMailboxSize, kMailboxWriteControl, 1)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(1), sm_config(kMailboxOut + 64, kMailboxSize, kMailboxReadControl, 1)).wkc, 1);
  EXPECT_EQ(request_state(*rig, kStation, AlState::pre_op, true), 0x0011);
  EXPECT_EQ(status_code(), 0x0016);
}

TEST_F(AlStateMachine, RequestsWithoutAcknowledgeAreIgnoredWhileTheErrorIsSet) {
  EXPECT_EQ(request_state(*rig, kStation, AlState::pre_op), 0x0011);
  configure_mailbox(*rig, kStation);
  EXPECT_EQ(request_state(*rig, kStation, AlState::pre_op), 0x0011);  // no acknowledge: ignored
  EXPECT_EQ(status_code(), 0x0016);
  EXPECT_EQ(request_state(*rig, kStation, AlState::pre_op, true), 0x0002);  // acknowledged and carried out
  EXPECT_EQ(status_code(), 0x0000);
}

TEST_F(AlStateMachine, AcknowledgeInTheSameStateClearsTheError) {
  to_pre_op();
  EXPECT_EQ(request_state(*rig, kStation, AlState::op), 0x0012);  // PRE-OP -> OP skips SAFE-OP
  EXPECT_EQ(status_code(), 0x0011);
  EXPECT_EQ(request_state(*rig, kStation, AlState::pre_op, true), 0x0002);
  EXPECT_EQ(status_code(), 0x0000);
}

TEST_F(AlStateMachine, InitIsAlwaysReachableEvenWithoutAcknowledge) {
  to_pre_op();
  EXPECT_EQ(request_state(*rig, kStation, AlState::op), 0x0012);
  EXPECT_EQ(request_state(*rig, kStation, AlState::init), 0x0001);
  EXPECT_EQ(status_code(), 0x0000);
}

TEST_F(AlStateMachine, JumpsUnknownStatesAndBootstrapAreRefused) {
  EXPECT_EQ(request_state(*rig, kStation, AlState::safe_op), 0x0011);
  EXPECT_EQ(status_code(), 0x0011);
  EXPECT_EQ(request_state(*rig, kStation, AlState::op, true), 0x0011);
  EXPECT_EQ(status_code(), 0x0011);
  (void)rig->write16(kStation, reg::kAlControl, 0x0015);  // state 5 does not exist (with acknowledge)
  EXPECT_EQ(status(), 0x0011);
  EXPECT_EQ(status_code(), 0x0012);
  EXPECT_EQ(request_state(*rig, kStation, AlState::boot, true), 0x0011);
  EXPECT_EQ(status_code(), 0x0013);
}

TEST_F(AlStateMachine, ProcessDataSyncManagersMustMatchTheDevice) {
  to_pre_op();
  // Outputs one byte short.
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(2), sm_config(kOutputs, kOutputBytes - 1, kOutputsControl, 1)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(3), sm_config(kInputs, kInputBytes, kInputsControl, 1)).wkc, 1);
  EXPECT_EQ(request_state(*rig, kStation, AlState::safe_op), 0x0012);
  EXPECT_EQ(status_code(), 0x001D);
  // Inputs written by the master instead of read.
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(2), sm_config(kOutputs, kOutputBytes, kOutputsControl, 0)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(2), sm_config(kOutputs, kOutputBytes, kOutputsControl, 1)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(3), sm_config(kInputs, kInputBytes, kInputsControl, 0)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(3), sm_config(kInputs, kInputBytes, kOutputsControl, 1)).wkc, 1);
  EXPECT_EQ(request_state(*rig, kStation, AlState::safe_op, true), 0x0012);
  EXPECT_EQ(status_code(), 0x001E);
  // Inputs' three buffers running into the mailbox: 0x0017.
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(3), sm_config(kInputs, kInputBytes, kInputsControl, 0)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(3), sm_config(kMailboxOut - 8, kInputBytes, kInputsControl, 1)).wkc, 1);
  EXPECT_EQ(request_state(*rig, kStation, AlState::safe_op, true), 0x0012);
  EXPECT_EQ(status_code(), 0x0017);
}

TEST_F(AlStateMachine, SafeOpToOpWaitsForTheFirstValidOutputs) {
  to_safe_op();
  EXPECT_EQ(request_state(*rig, kStation, AlState::op), 0x0004);  // no outputs yet: still SAFE-OP, no error
  EXPECT_EQ(status(), 0x0004);
  send_outputs();
  EXPECT_EQ(status(), 0x0008);
  EXPECT_EQ(status_code(), 0x0000);
}

TEST_F(AlStateMachine, SafeOpToOpWithoutOutputsTimesOut) {
  to_safe_op();
  EXPECT_EQ(request_state(*rig, kStation, AlState::op), 0x0004);
  rig->wait(Esc::kSafeOpToOpTimeout + hal::kNsPerMs);
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(status_code(), 0x001B);
}

TEST_F(AlStateMachine, DeviceRefusalCarriesItsOwnCode) {
  rig->device().refuse_op = 0x0030;  // e.g. invalid DC SYNC configuration
  to_safe_op();
  send_outputs();
  EXPECT_EQ(request_state(*rig, kStation, AlState::op), 0x0014);
  EXPECT_EQ(status_code(), 0x0030);
}

TEST_F(AlStateMachine, ProcessDataWatchdogDropsOpToSafeOpWithError) {
  to_safe_op();
  send_outputs();
  ASSERT_EQ(request_state(*rig, kStation, AlState::op), 0x0008);
  EXPECT_EQ(rig->read16(kStation, reg::kWatchdogStatusProcessData) & 0x01, 0x01);
  // 100 ms without outputs (watchdog 1000 x 100 us by default).
  rig->wait(99 * hal::kNsPerMs);
  EXPECT_EQ(status(), 0x0008);
  rig->wait(2 * hal::kNsPerMs);
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(status_code(), 0x001B);
  EXPECT_EQ(rig->read16(kStation, reg::kWatchdogStatusProcessData) & 0x01, 0x00);
  EXPECT_EQ(rig->read(Command::FPRD, kStation, 0x0442, 1).data[0], 1);  // watchdog counter
  // The master acknowledges and brings it back.
  EXPECT_EQ(request_state(*rig, kStation, AlState::safe_op, true), 0x0004);
  send_outputs();
  EXPECT_EQ(request_state(*rig, kStation, AlState::op), 0x0008);
}

TEST_F(AlStateMachine, DownwardTransitionsSwitchSyncManagersOff) {
  to_safe_op();
  send_outputs();
  ASSERT_EQ(request_state(*rig, kStation, AlState::op), 0x0008);
  EXPECT_EQ(request_state(*rig, kStation, AlState::pre_op), 0x0002);
  EXPECT_EQ(rig->read(Command::FPRD, kStation, reg::sync_manager(2) + reg::kSmPdiControl, 1).data[0] & 0x01, 0x01);
  EXPECT_EQ(rig->exchange(Command::LRW, 0x1000, std::vector<std::uint8_t>(14, 1)).wkc, 0);  // process data locked
  EXPECT_EQ(request_state(*rig, kStation, AlState::init), 0x0001);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, std::vector<std::uint8_t>(kMailboxSize, 0)).wkc, 0);  // mailbox locked
  const auto& t = rig->device().transitions;
  ASSERT_GE(t.size(), 2u);
  EXPECT_EQ(t.back(), std::make_pair(AlState::pre_op, AlState::init));
}

TEST_F(AlStateMachine, ApplicationErrorDropsTheStateWithItsCode) {
  to_safe_op();
  send_outputs();
  ASSERT_EQ(request_state(*rig, kStation, AlState::op), 0x0008);
  rig->segment.esc(0).raise_al_error(AlState::safe_op, 0x0032);
  EXPECT_EQ(status(), 0x0014);
  EXPECT_EQ(status_code(), 0x0032);
}

TEST_F(AlStateMachine, AlControlIsRefusedWhileTheApplicationHasNotReadTheLastRequest) {
  ASSERT_TRUE(rig->segment.freeze(0, true).ok());
  configure_mailbox(*rig, kStation);
  EXPECT_EQ(rig->write16(kStation, reg::kAlControl, 0x0002), 1);
  EXPECT_EQ(rig->write16(kStation, reg::kAlControl, 0x0002), 0);  // not read yet by the hung application
  EXPECT_EQ(status(), 0x0001);
  ASSERT_TRUE(rig->segment.freeze(0, false).ok());
  EXPECT_EQ(status(), 0x0002);  // served at the end of the next frame
}

TEST(AlDeviceEmulation, JunctionStatusFollowsControlWithoutChecks) {
  auto rig = Rig::robot();
  rig->assign_station_addresses();
  EXPECT_TRUE(rig->segment.esc(0).device_emulation());
  EXPECT_EQ(rig->write16(0x1000, reg::kAlControl, 0x0011), 1);
  EXPECT_EQ(rig->read16(0x1000, reg::kAlStatus), 0x0011);  // the acknowledge bit is copied too, as on real couplers
  EXPECT_EQ(rig->write16(0x1000, reg::kAlControl, 0x0008), 1);
  EXPECT_EQ(rig->read16(0x1000, reg::kAlStatus), 0x0008);  // INIT -> OP without complaint
  EXPECT_EQ(rig->write16(0x1000, reg::kAlControl, 0x0008), 1);  // no application to read it: never refused
}

}  // namespace
}  // namespace rescue::drivers::testing
