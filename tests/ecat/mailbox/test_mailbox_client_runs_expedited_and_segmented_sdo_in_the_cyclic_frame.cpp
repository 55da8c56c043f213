// The master's cyclic mailbox channel (ecat/mailbox/mailbox_client.hpp) against the simulated robot
// in OP, in virtual time, one mailbox step per cyclic frame: expedited upload (0x603F error code,
// 0x2002 temperature), segmented upload of a value longer than one mailbox (0x100A firmware
// version, 152 bytes through a 128-byte mailbox), expedited download read back, segmented download
// of a 160-byte string read back, an SDO abort with its code, a timeout (a hung drive), a full
// queue refused at submit while everything already queued completes (nothing lost), and the
// operator's completions kept apart from the owner's. Every frame of it carries every joint.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "ecat/mailbox/coe.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

class CyclicMailbox : public ::testing::Test {
 protected:
  void SetUp() override {
    rig = testing::simulated_robot_in_op();
    elbow = static_cast<std::uint8_t>(slave_position_of_joint(joint_index_by_name("l_elbow")));
  }
  MailboxClient& mailbox() { return rig->bus.master().mailbox(); }
  // Cycles until `count` completions (owner's queue, or the operator's) arrived; every cycle's
  // frame must carry every joint.
  std::vector<SdoCompletion> run_until(std::size_t count, bool operator_queue = false, int max_cycles = 2000) {
    std::vector<SdoCompletion> done;
    for (int i = 0; i < max_cycles && done.size() < count; ++i) {
      const drivers::JointCycleResult r = rig->cycle(refs, fb);
      EXPECT_EQ(r.valid, kAllJoints) << "a mailbox step never costs a joint its cycle (cycle " << i << ")";
      SdoCompletion c;
      while (operator_queue ? mailbox().pop_operator_completion(c) : mailbox().pop_completion(c)) done.push_back(c);
    }
    return done;
  }
  static std::string text_of(const SdoCompletion& c) {
    return std::string(reinterpret_cast<const char*>(c.data.data()), c.size);
  }

  std::unique_ptr<testing::SimulatedRobotRig> rig;
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  std::uint8_t elbow{0};
};

TEST_F(CyclicMailbox, ExpeditedUploadsReadTheErrorCodeAndTheTemperature) {
  ASSERT_TRUE(mailbox().submit(sdo_upload(elbow, 0x603F, 0, 1)));
  ASSERT_TRUE(mailbox().submit(sdo_upload(elbow, 0x2002, 0, 2)));
  const std::vector<SdoCompletion> done = run_until(2);
  ASSERT_EQ(done.size(), 2U);
  EXPECT_EQ(done[0].outcome, SdoOutcome::ok);
  EXPECT_EQ(done[0].size, 2U);
  EXPECT_EQ(sdo_value(done[0]), 0U);
  EXPECT_FALSE(done[0].segmented);
  EXPECT_EQ(done[1].outcome, SdoOutcome::ok);
  EXPECT_EQ(done[1].size, 2U);
  EXPECT_EQ(static_cast<std::int16_t>(sdo_value(done[1])), drivers::kDriveTemperatureIdleDeciC);
}

TEST_F(CyclicMailbox, SegmentedUploadReadsTheWholeFirmwareVersion) {
  const std::string expected = drivers::kJointDriveFirmwareVersion;
  ASSERT_GT(expected.size(), drivers::kJointMailboxSize) << "longer than one mailbox: it must travel in segments";
  ASSERT_TRUE(mailbox().submit(sdo_upload(elbow, 0x100A, 0, 3)));
  const std::vector<SdoCompletion> done = run_until(1);
  ASSERT_EQ(done.size(), 1U);
  EXPECT_EQ(done[0].outcome, SdoOutcome::ok) << to_string(done[0].outcome);
  EXPECT_TRUE(done[0].segmented);
  EXPECT_EQ(text_of(done[0]), expected);
  // Initiate + at least one segment, each a send and a wait: more than one exchange, but bounded.
  EXPECT_GE(done[0].exchanges, 4U);
  EXPECT_LE(done[0].exchanges, 20U);
}

TEST_F(CyclicMailbox, ExpeditedAndSegmentedDownloadsReadBack) {
  const std::string label(160, 'x');
  std::string written = label;
  for (std::size_t i = 0; i < written.size(); ++i) written[i] = static_cast<char>('a' + i % 26);
  ASSERT_TRUE(mailbox().submit(sdo_download(elbow, 0x6065, 0, 5000, 4, 1)));
  ASSERT_TRUE(mailbox().submit(sdo_upload(elbow, 0x6065, 0, 2)));
  ASSERT_TRUE(mailbox().submit(sdo_download_bytes(
      elbow, 0x2010, 0, ConstByteSpan(reinterpret_cast<const std::uint8_t*>(written.data()), written.size()), 3)));
  ASSERT_TRUE(mailbox().submit(sdo_upload(elbow, 0x2010, 0, 4)));
  const std::vector<SdoCompletion> done = run_until(4);
  ASSERT_EQ(done.size(), 4U);
  for (const SdoCompletion& c : done) EXPECT_EQ(c.outcome, SdoOutcome::ok) << c.request.tag << ": " << to_string(c.outcome);
  EXPECT_EQ(sdo_value(done[1]), 5000U);
  EXPECT_FALSE(done[0].segmented);
  EXPECT_TRUE(done[2].segmented) << "160 bytes do not fit one 128-byte mailbox";
  EXPECT_EQ(text_of(done[3]), written);
  EXPECT_EQ(rig->drive(joint_index_by_name("l_elbow")).objects().od().read(0x2010, 0).bytes.size(), 160U);
}

TEST_F(CyclicMailbox, AbortsComeBackWithTheirCode) {
  ASSERT_TRUE(mailbox().submit(sdo_upload(elbow, 0x5FFF, 0, 1)));
  ASSERT_TRUE(mailbox().submit(sdo_download(elbow, 0x1008, 0, 0x41, 1, 2)));  // read-only
  const std::string too_long(161, 'y');                                            // capacity 160
  ASSERT_TRUE(mailbox().submit(sdo_download_bytes(
      elbow, 0x2010, 0, ConstByteSpan(reinterpret_cast<const std::uint8_t*>(too_long.data()), too_long.size()), 3)));
  const std::vector<SdoCompletion> done = run_until(3);
  ASSERT_EQ(done.size(), 3U);
  EXPECT_EQ(done[0].outcome, SdoOutcome::aborted);
  EXPECT_EQ(done[0].abort_code, coe::abort_code::kObjectDoesNotExist);
  EXPECT_EQ(done[1].outcome, SdoOutcome::aborted);
  EXPECT_EQ(done[1].abort_code, coe::abort_code::kReadOnly);
  EXPECT_EQ(done[2].outcome, SdoOutcome::aborted);
  EXPECT_EQ(done[2].abort_code, coe::abort_code::kLengthTooHigh);
  EXPECT_STREQ(coe::explain_abort_code(done[0].abort_code), "object does not exist in the object dictionary");
}

TEST_F(CyclicMailbox, HungDriveTimesOutAndTheNextTransferRuns) {
  ASSERT_TRUE(rig->segment.freeze(elbow, true).ok());
  ASSERT_TRUE(mailbox().submit(sdo_upload(elbow, 0x1008, 0, 1)));
  std::vector<SdoCompletion> done;
  for (int i = 0; i < 400 && done.empty(); ++i) {
    (void)rig->cycle(refs, fb);
    SdoCompletion c;
    while (mailbox().pop_completion(c)) done.push_back(c);
  }
  ASSERT_EQ(done.size(), 1U);
  EXPECT_EQ(done[0].outcome, SdoOutcome::timeout);
  ASSERT_TRUE(rig->segment.freeze(elbow, false).ok());
  const std::uint8_t neck = static_cast<std::uint8_t>(slave_position_of_joint(joint_index_by_name("neck_pan")));
  ASSERT_TRUE(mailbox().submit(sdo_upload(neck, 0x1008, 0, 2)));
  std::vector<SdoCompletion> next;
  for (int i = 0; i < 400 && next.empty(); ++i) {
    (void)rig->cycle(refs, fb);  // the hung drive may be on its way back: its joint's cycles are not judged here
    SdoCompletion c;
    while (mailbox().pop_completion(c)) next.push_back(c);
  }
  ASSERT_EQ(next.size(), 1U);
  EXPECT_EQ(next[0].outcome, SdoOutcome::ok);
}

TEST_F(CyclicMailbox, FullQueueRefusesAtSubmitAndLosesNothingQueued) {
  std::size_t accepted = 0;
  while (mailbox().submit(sdo_upload(elbow, 0x1018, 1, static_cast<std::uint32_t>(accepted)))) ++accepted;
  EXPECT_EQ(accepted, MailboxClient::kQueueCapacity);
  EXPECT_EQ(mailbox().free_slots(), 0U);
  const std::vector<SdoCompletion> done = run_until(accepted, false, 5000);
  ASSERT_EQ(done.size(), accepted);
  for (std::size_t i = 0; i < done.size(); ++i) {
    EXPECT_EQ(done[i].request.tag, i);
    EXPECT_EQ(done[i].outcome, SdoOutcome::ok);
  }
}

TEST_F(CyclicMailbox, OperatorCompletionsHaveTheirOwnQueue) {
  ASSERT_TRUE(mailbox().submit(sdo_upload(elbow, 0x100A, 0, MailboxClient::kOperatorTagBit | 7)));
  ASSERT_TRUE(mailbox().submit(sdo_upload(elbow, 0x1008, 0, 8)));
  const std::vector<SdoCompletion> owner = run_until(1);
  ASSERT_EQ(owner.size(), 1U);
  EXPECT_EQ(owner[0].request.tag, 8U);
  SdoCompletion c;
  ASSERT_TRUE(mailbox().pop_operator_completion(c));
  EXPECT_EQ(c.request.tag, MailboxClient::kOperatorTagBit | 7);
  EXPECT_EQ(text_of(c), drivers::kJointDriveFirmwareVersion);
  EXPECT_FALSE(mailbox().pop_completion(c));
}

}  // namespace
}  // namespace rescue::ecat
