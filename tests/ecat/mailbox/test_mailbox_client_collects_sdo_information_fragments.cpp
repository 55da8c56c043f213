// The SDO client's SDO Information requests (ecat/mailbox/mailbox_client.hpp, direction
// information; ctl sdos) against a simulated drive's dictionary behind a fake NIC with a short SM1
// (40 bytes, so a Get OD List response comes in several fragments, posted one after the other as
// the drive does): the fragments are joined into the whole list, a window from an offset keeps only
// those bytes and still reports the whole length, object and entry descriptions decode, an SDO Info
// Error completes aborted with its code, and a lost fragment is a bad response, never a wrong list.
#include <gtest/gtest.h>

#include <cstring>
#include <deque>
#include <vector>

#include "drivers/joint/robot_network_plan.hpp"
#include "drivers/sim/coe/coe_sdo_server.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/coe_information.hpp"
#include "ecat/mailbox/mailbox.hpp"
#include "ecat/mailbox/mailbox_client.hpp"

namespace rescue::ecat {
namespace {

using drivers::kRobotNetworkPlan;
namespace info = coe::info;

constexpr std::uint16_t kOut = 0x1000, kIn = 0x1080, kOutSize = 128, kInSize = 40;
constexpr std::uint8_t kSlave = 4;  // r_shoulder_yaw

// One slave's mailboxes, answered from a drive's object dictionary; every fragment of an answer is
// queued in SM1 at once, read one per SM1 read.
class FakeDictionaryNic final : public hal::Nic {
 public:
  explicit FakeDictionaryNic(drivers::JointDriveObjects& objects) : objects_(objects) {}
  bool drop_second_fragment = false;

  Status send(ConstByteSpan frame) noexcept override {
    std::vector<std::uint8_t> f(frame.begin(), frame.end());
    auto view = MutableFrameView::parse(ByteSpan(f.data(), f.size()));
    for (const MutableDatagramView d : view.value()) handle(d);
    frames_.push_back(std::move(f));
    clock_.advance(10'000);
    return Status::success();
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    if (frames_.empty()) {
      clock_.sleep_until(deadline);
      return make_error(Errc::timeout, "no frame");
    }
    std::memcpy(buffer.data(), frames_.front().data(), frames_.front().size());
    const std::size_t n = frames_.front().size();
    frames_.pop_front();
    return n;
  }
  hal::Clock& clock() noexcept override { return clock_; }
  const char* name() const noexcept override { return "fake dictionary"; }
  hal::NicStats stats() const noexcept override { return {}; }

 private:
  void handle(const MutableDatagramView& d) {
    if (d.adp() != kRobotNetworkPlan[kSlave].station_address) return;
    if (d.command() == Command::FPWR && d.ado() == kOut) {
      d.set_wkc(1);
      answer(ConstByteSpan(d.data()));
    } else if (d.command() == Command::FPRD && d.ado() == reg::sync_manager(1) + reg::kSmStatus) {
      d.data()[0] = pending_.empty() ? 0 : reg::kSmStatusMailboxFull;
      d.set_wkc(1);
    } else if (d.command() == Command::FPRD && d.ado() == kIn && !pending_.empty()) {
      std::memcpy(d.data().data(), pending_.front().data(), kInSize);
      pending_.pop_front();
      d.set_wkc(1);
    }
  }
  void answer(ConstByteSpan request) {
    std::vector<std::uint8_t> out(kInSize, 0);
    // Every message with the next mailbox counter, as a slave sends them (the master drops one
    // with the counter of the message before as a repeat).
    counter_ = mbx::next_counter(counter_);
    const std::size_t n = drivers::serve_sdo(request, objects_.od(), reg::AlState::op, ByteSpan(out.data(), out.size()), counter_);
    if (n == 0) return;
    pending_.push_back(out);
    for (std::uint16_t fragment = 1;; ++fragment) {
      std::vector<std::uint8_t> next(kInSize, 0);
      counter_ = mbx::next_counter(counter_);
      if (drivers::serve_sdo_fragment(request, objects_.od(), ByteSpan(next.data(), next.size()), counter_, fragment) == 0) return;
      if (!(drop_second_fragment && fragment == 1)) pending_.push_back(next);
    }
  }

  drivers::JointDriveObjects& objects_;
  hal::VirtualClock clock_;
  std::deque<std::vector<std::uint8_t>> frames_;
  std::deque<std::vector<std::uint8_t>> pending_;
  std::uint8_t counter_{0};
};

class SdoInformationClient : public ::testing::Test {
 protected:
  void SetUp() override { client.configure(kSlave, kOut, kOutSize, kIn, kInSize); }
  SdoCompletion run_one(const SdoRequest& request) {
    EXPECT_TRUE(client.submit(request));
    EXPECT_TRUE(client.run(link, hal::kNsPerMs, hal::kNsPerSec).ok());
    SdoCompletion c;
    EXPECT_TRUE(client.pop_completion(c));
    EXPECT_FALSE(client.pop_completion(c)) << "one completion per request";
    return c;
  }
  std::vector<std::uint16_t> all_indexes() const {
    std::vector<std::uint16_t> v;
    for (const drivers::ObjectEntry& e : objects.od().entries()) {
      if (v.empty() || v.back() != e.index) v.push_back(e.index);
    }
    return v;
  }

  drivers::JointDriveObjects objects{joint_index_by_name("r_elbow"), slave_position_of_joint(joint_index_by_name("r_elbow"))};
  FakeDictionaryNic nic{objects};
  DatagramLink link{nic};
  MailboxClient client{kRobotNetworkPlan};
};

TEST_F(SdoInformationClient, TheFragmentsOfAnOdListJoinIntoEveryIndex) {
  const SdoCompletion c = run_one(sdo_information(kSlave, info::kGetOdListRequest, info::kListAll, 0, 0, 7));
  ASSERT_EQ(c.outcome, SdoOutcome::ok) << to_string(c.outcome);
  EXPECT_TRUE(c.segmented) << "a 40-byte SM1 cuts the list into fragments";
  EXPECT_EQ(c.request.tag, 7U);
  const std::vector<std::uint16_t> expected = all_indexes();
  EXPECT_EQ(c.info_total, 2 + 2 * expected.size());
  ASSERT_EQ(c.size, c.info_total);
  const Result<info::OdList> list = info::decode_od_list(ConstByteSpan(c.data.data(), c.size));
  ASSERT_TRUE(list.ok());
  EXPECT_EQ(list.value().list_type, info::kListAll);
  std::vector<std::uint16_t> got;
  for (std::size_t i = 0; i < list.value().count; ++i) got.push_back(list.value().index(i));
  EXPECT_EQ(got, expected);
}

TEST_F(SdoInformationClient, AWindowKeepsTheBytesFromItsOffsetAndReportsTheWholeLength) {
  const SdoCompletion whole = run_one(sdo_information(kSlave, info::kGetOdListRequest, info::kListAll, 0, 0));
  const SdoCompletion window = run_one(sdo_information(kSlave, info::kGetOdListRequest, info::kListAll, 0, 32));
  ASSERT_EQ(window.outcome, SdoOutcome::ok);
  EXPECT_EQ(window.info_total, whole.info_total);
  ASSERT_EQ(window.size, whole.size - 32U);
  EXPECT_EQ(std::memcmp(window.data.data(), whole.data.data() + 32, window.size), 0);
  const SdoCompletion past = run_one(sdo_information(kSlave, info::kGetOdListRequest, info::kListAll, 0, 4000));
  ASSERT_EQ(past.outcome, SdoOutcome::ok);
  EXPECT_EQ(past.size, 0U);
  EXPECT_EQ(past.info_total, whole.info_total);
}

TEST_F(SdoInformationClient, ObjectAndEntryDescriptionsDecode) {
  const SdoCompletion object = run_one(sdo_information(kSlave, info::kGetObjectDescriptionRequest, 0x1018, 0, 0));
  ASSERT_EQ(object.outcome, SdoOutcome::ok);
  const Result<info::ObjectDescription> o = info::decode_object_description(ConstByteSpan(object.data.data(), object.size));
  ASSERT_TRUE(o.ok());
  EXPECT_EQ(o.value().index, 0x1018);
  EXPECT_STREQ(info::object_code_name(o.value().object_code), "RECORD");
  EXPECT_EQ(o.value().max_subindex, 4);

  const SdoCompletion entry = run_one(sdo_information(kSlave, info::kGetEntryDescriptionRequest, 0x6041, 0, 0));
  ASSERT_EQ(entry.outcome, SdoOutcome::ok);
  const Result<info::EntryDescription> e = info::decode_entry_description(ConstByteSpan(entry.data.data(), entry.size));
  ASSERT_TRUE(e.ok());
  EXPECT_EQ(e.value().index, 0x6041);
  EXPECT_STREQ(info::data_type_name(e.value().data_type), "UNSIGNED16");
  EXPECT_EQ(e.value().bit_length, 16);
  EXPECT_NE(e.value().access & 0x0080U, 0U) << "the statusword is TxPDO-mapped";
}

TEST_F(SdoInformationClient, AnSdoInfoErrorCompletesAbortedWithItsCode) {
  const SdoCompletion c = run_one(sdo_information(kSlave, info::kGetObjectDescriptionRequest, 0x5FFF, 0, 0));
  EXPECT_EQ(c.outcome, SdoOutcome::aborted);
  EXPECT_EQ(c.abort_code, coe::abort_code::kObjectDoesNotExist);
  const SdoCompletion sub = run_one(sdo_information(kSlave, info::kGetEntryDescriptionRequest, 0x1018, 9, 0));
  EXPECT_EQ(sub.outcome, SdoOutcome::aborted);
  EXPECT_EQ(sub.abort_code, coe::abort_code::kSubindexDoesNotExist);
}

TEST_F(SdoInformationClient, ALostFragmentIsABadResponse) {
  nic.drop_second_fragment = true;
  const SdoCompletion c = run_one(sdo_information(kSlave, info::kGetOdListRequest, info::kListAll, 0, 0));
  EXPECT_EQ(c.outcome, SdoOutcome::bad_response);
}

}  // namespace
}  // namespace rescue::ecat
