// SOEM 2.x maps one more read FMMU on every mailbox slave (ecx_config_create_mbxstatus_mappings):
// one logical byte onto the SM1 status register 0x080D, placed after all inputs, so each cycle's
// LRW tells which slave has a mailbox answer waiting. Real ESCs map register space like RAM. This
// shows the simulated ESC doing the same: the byte follows SM1's "full" bit, reading it through the
// FMMU does not take the answer away, and the ESC counts its read once in the LRW working counter
// although two of its read FMMUs (inputs and status) match (SOEM expects no extra count from a
// slave that has inputs).
#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {
namespace {

constexpr std::uint16_t kStation = 0x1000;
constexpr std::uint16_t kSm1Status = 0x080D;
constexpr std::uint32_t kLogical = 0x00010000;
// LRW image: outputs, inputs, then the mailbox status byte.
constexpr std::uint32_t kStatusLogical = kLogical + kOutputBytes + kInputBytes;
constexpr std::size_t kImage = kOutputBytes + kInputBytes + 1;

std::vector<std::uint8_t> request_message() {
  std::vector<std::uint8_t> m(kMailboxSize, 0);
  m[0] = 10;    // mailbox length
  m[5] = 0x13;  // counter 1, CoE
  return m;
}

class MailboxStatusFmmu : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = Rig::single();
    rig->assign_station_addresses();
    configure_mailbox(*rig, kStation);
    ASSERT_EQ(request_state(*rig, kStation, AlState::pre_op), 0x0002);
    configure_process_data(*rig, kStation, kLogical);
    // What SOEM 2.x writes: FMMU2, 1 byte at kStatusLogical, physical 0x080D, read, active.
    ASSERT_EQ(rig->write(Command::FPWR, kStation, reg::fmmu(2), fmmu_config(kStatusLogical, 1, kSm1Status, 1)).wkc, 1);
    ASSERT_EQ(request_state(*rig, kStation, AlState::safe_op), 0x0004);
  }
  DatagramResult lrw() { return rig->exchange(Command::LRW, kLogical, std::vector<std::uint8_t>(kImage, 0)); }
  std::unique_ptr<Rig> rig;
};

TEST_F(MailboxStatusFmmu, TheStatusByteShowsAWaitingAnswerAndTheEscCountsItsReadOnce) {
  DatagramResult r = lrw();
  EXPECT_EQ(r.wkc, 3);  // outputs written (+2) and inputs read (+1): the status FMMU adds nothing
  ASSERT_EQ(r.data.size(), kImage);
  EXPECT_EQ(r.data[kImage - 1] & 0x08, 0);  // nothing waiting

  ASSERT_EQ(rig->write(Command::FPWR, kStation, kMailboxOut, request_message()).wkc, 1);  // the device echoes it
  r = lrw();
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data[kImage - 1] & 0x08, 0x08);  // SM1 full: an answer waits
  r = lrw();
  EXPECT_EQ(r.data[kImage - 1] & 0x08, 0x08);  // reading the status does not consume the answer

  EXPECT_EQ(rig->read(Command::FPRD, kStation, kMailboxIn, kMailboxSize).wkc, 1);  // the master reads it
  r = lrw();
  EXPECT_EQ(r.data[kImage - 1] & 0x08, 0);
}

TEST_F(MailboxStatusFmmu, AnLrdOfTheStatusByteAloneCountsOne) {
  const auto r = rig->exchange(Command::LRD, kStatusLogical, std::vector<std::uint8_t>(1, 0xFF));
  EXPECT_EQ(r.wkc, 1);
  ASSERT_EQ(r.data.size(), 1u);
  EXPECT_EQ(r.data[0], rig->read(Command::FPRD, kStation, kSm1Status, 1).data[0]);
}

}  // namespace
}  // namespace rescue::drivers::testing
