// SyncManagers as masters meet them: mailboxes that accept a write only when empty and a read only
// when full (full/empty in the status register, no working counter otherwise), the device's answer
// queued behind earlier ones, the repeat request; three-buffer process data where the reader always
// gets the newest complete buffer; configuration registers locked while enabled; SyncManagers the
// device switched off lock their memory.
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr std::uint16_t kStation = 0x1000;
constexpr std::uint32_t kSm0Status = 0x0805;
constexpr std::uint32_t kSm1Status = 0x080D;

std::vector<std::uint8_t> message(std::uint8_t tag) {
  std::vector<std::uint8_t> m(kMailboxSize, 0);
  m[0] = 10;  // mailbox header: length 10
  m[5] = 0x03;  // CoE
  for (std::size_t i = 6; i < 16; ++i) m[i] = tag;
  return m;
}

class SyncManagers : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = Rig::single();
    rig->assign_station_addresses();
    configure_mailbox(*rig, kStation);
    ASSERT_EQ(request_state(*rig, kStation, AlState::pre_op), 0x0002);
  }
  std::uint8_t status(std::uint32_t reg_address) { return rig->read(Command::FPRD, kStation, static_cast<std::uint16_t>(reg_address), 1).data[0]; }
  std::unique_ptr<Rig> rig;
};

TEST_F(SyncManagers, MailboxWriteReachesTheDeviceAndItsAnswerIsReadOnce) {
  EXPECT_EQ(status(kSm1Status) & 0x08, 0);  // nothing to read
  EXPECT_EQ(rig->read(Command::FPRD, kStation, kMailboxIn, kMailboxSize).wkc, 0);  // empty: refused
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, message(0x42)).wkc, 1);
  ASSERT_EQ(rig->device().received.size(), 1u);
  EXPECT_EQ(rig->device().received[0], message(0x42));
  EXPECT_EQ(status(kSm0Status), 0x02);  // read by the device, empty again
  EXPECT_EQ(status(kSm1Status) & 0x09, 0x09);  // written and full
  const auto answer = rig->read(Command::FPRD, kStation, kMailboxIn, kMailboxSize);
  EXPECT_EQ(answer.wkc, 1);
  const auto sent = message(0x42);
  EXPECT_EQ(std::vector<std::uint8_t>(answer.data.begin(), answer.data.begin() + 16),
            std::vector<std::uint8_t>(sent.begin(), sent.begin() + 16));
  EXPECT_EQ(answer.data[16], 0);
  EXPECT_EQ(status(kSm1Status) & 0x0B, 0x02);  // read, empty
  EXPECT_EQ(rig->read(Command::FPRD, kStation, kMailboxIn, kMailboxSize).wkc, 0);
}

TEST_F(SyncManagers, MailboxIsFullOnlyOnceItsLastByteIsWritten) {
  const auto m = message(1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, std::vector<std::uint8_t>(m.begin(), m.begin() + 64)).wkc, 1);
  EXPECT_TRUE(rig->device().received.empty());
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut + kMailboxSize - 1, {0}).wkc, 1);
  EXPECT_EQ(rig->device().received.size(), 1u);
}

TEST_F(SyncManagers, FullMailboxRefusesTheNextWrite) {
  ASSERT_TRUE(rig->segment.freeze(0, true).ok());  // the device does not read it
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, message(1)).wkc, 1);
  EXPECT_EQ(status(kSm0Status) & 0x08, 0x08);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, message(2)).wkc, 0);
  ASSERT_TRUE(rig->segment.freeze(0, false).ok());
  rig->wait(hal::kNsPerUs);
  ASSERT_EQ(rig->device().received.size(), 1u);
  EXPECT_EQ(rig->device().received[0][6], 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, message(2)).wkc, 1);
}

TEST_F(SyncManagers, AnswersQueueUntilTheMasterReadsThem) {
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, message(1)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, message(2)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, message(3)).wkc, 1);
  for (std::uint8_t tag = 1; tag <= 3; ++tag) {
    const auto r = rig->read(Command::FPRD, kStation, kMailboxIn, kMailboxSize);
    ASSERT_EQ(r.wkc, 1);
    EXPECT_EQ(r.data[6], tag);
  }
  EXPECT_EQ(rig->read(Command::FPRD, kStation, kMailboxIn, kMailboxSize).wkc, 0);
}

TEST_F(SyncManagers, RepeatRequestPostsTheLastAnswerAgain) {
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, message(7)).wkc, 1);
  EXPECT_EQ(rig->read(Command::FPRD, kStation, kMailboxIn, kMailboxSize).wkc, 1);  // "lost" by the master
  const std::uint32_t activate = reg::sync_manager(1) + reg::kSmActivate;
  EXPECT_EQ(rig->write(Command::FPWR, kStation, static_cast<std::uint16_t>(activate), {0x03}).wkc, 1);  // toggle repeat
  EXPECT_EQ(rig->read(Command::FPRD, kStation, static_cast<std::uint16_t>(activate + 1), 1).data[0] & 0x02, 0x02);  // acknowledged
  const auto again = rig->read(Command::FPRD, kStation, kMailboxIn, kMailboxSize);
  EXPECT_EQ(again.wkc, 1);
  EXPECT_EQ(again.data[6], 7);
}

TEST_F(SyncManagers, ConfigurationIsWriteProtectedWhileEnabled) {
  const auto sm1 = static_cast<std::uint16_t>(reg::sync_manager(1));
  EXPECT_EQ(rig->write(Command::FPWR, kStation, sm1, le16(0x1800)).wkc, 0);  // start address: locked
  EXPECT_EQ(rig->read16(kStation, sm1), kMailboxIn);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, sm1, sm_config(0x1800, kMailboxSize, kMailboxReadControl, 1)).wkc, 1);  // counts (activate)
  EXPECT_EQ(rig->read16(kStation, sm1), kMailboxIn);  // but the locked part did not change
}

TEST_F(SyncManagers, DeactivatedByTheDeviceLocksTheArea) {
  // In PRE-OP the process-data SyncManagers are off on the device side: the master's enable does
  // not open them.
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(2), sm_config(kOutputs, kOutputBytes, kOutputsControl, 1)).wkc, 1);
  EXPECT_EQ(rig->read(Command::FPRD, kStation, static_cast<std::uint16_t>(reg::sync_manager(2) + reg::kSmPdiControl), 1).data[0] & 0x01, 0x01);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kOutputs, std::vector<std::uint8_t>(kOutputBytes, 1)).wkc, 0);
  // A disabled SyncManager leaves plain memory.
  EXPECT_EQ(rig->write(Command::FPWR, kStation, reg::sync_manager(2), sm_config(kOutputs, kOutputBytes, kOutputsControl, 0)).wkc, 1);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kOutputs, std::vector<std::uint8_t>(kOutputBytes, 1)).wkc, 1);
}

class Buffered : public SyncManagers {
 protected:
  void SetUp() override {
    SyncManagers::SetUp();
    configure_process_data(*rig, kStation, 0x1000);
    ASSERT_EQ(request_state(*rig, kStation, AlState::safe_op), 0x0004);
  }
};

TEST_F(Buffered, OutputsWrittenCompletelyRunTheApplicationCycle) {
  const std::size_t before = rig->device().cycles.size();
  EXPECT_EQ(rig->exchange(Command::LWR, 0x1000, {1, 2, 3, 4, 5, 6}).wkc, 1);
  ASSERT_EQ(rig->device().cycles.size(), before + 1);
  EXPECT_EQ(rig->device().cycles.back().trigger, CycleTrigger::sm_event);
  EXPECT_EQ(rig->device().cycles.back().state, AlState::safe_op);
  EXPECT_EQ(rig->device().last_outputs, (std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6}));
  // Half the outputs do not complete a buffer.
  EXPECT_EQ(rig->exchange(Command::LWR, 0x1000, {9, 9, 9}).wkc, 1);
  EXPECT_EQ(rig->device().cycles.size(), before + 1);
}

TEST_F(Buffered, TheMasterReadsTheNewestCompleteInputs) {
  // The test device copies outputs into inputs each cycle: two cycles, then one read.
  EXPECT_EQ(rig->exchange(Command::LWR, 0x1000, {1, 1, 1, 1, 1, 1}).wkc, 1);
  EXPECT_EQ(rig->exchange(Command::LWR, 0x1000, {2, 2, 2, 2, 2, 2}).wkc, 1);
  const auto inputs = rig->exchange(Command::LRD, 0x1000 + kOutputBytes, std::vector<std::uint8_t>(kInputBytes, 0));
  EXPECT_EQ(inputs.wkc, 1);
  EXPECT_EQ(inputs.data[0], 2);
  // Reading again gives the same buffer (nothing newer).
  EXPECT_EQ(rig->exchange(Command::LRD, 0x1000 + kOutputBytes, std::vector<std::uint8_t>(kInputBytes, 0)).data[0], 2);
}

TEST_F(Buffered, LrwExchangesOutputsAndInputsInOneFrame) {
  EXPECT_EQ(rig->exchange(Command::LRW, 0x1000, std::vector<std::uint8_t>(kOutputBytes + kInputBytes, 3)).wkc, 3);
  // Inputs are produced by the cycle the outputs triggered: the next frame carries them.
  const auto lrw = rig->exchange(Command::LRW, 0x1000, std::vector<std::uint8_t>(kOutputBytes + kInputBytes, 4));
  EXPECT_EQ(lrw.wkc, 3);
  EXPECT_EQ(lrw.data[kOutputBytes], 3);
}

TEST_F(Buffered, OutputsCannotBeReadBackNorInputsWritten) {
  EXPECT_EQ(rig->read(Command::FPRD, kStation, kOutputs, kOutputBytes).wkc, 0);
  EXPECT_EQ(rig->write(Command::FPWR, kStation, kInputs, std::vector<std::uint8_t>(kInputBytes, 0)).wkc, 0);
}

}  // namespace
}  // namespace rescue::drivers::testing
