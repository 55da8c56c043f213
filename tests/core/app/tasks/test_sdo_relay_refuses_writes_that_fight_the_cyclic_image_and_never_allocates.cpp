// ctl upload/download on the EtherCAT handler's side (core/app/tasks/sdo_relay.hpp), with the real
// handler, master and joint manager on the simulated robot in virtual time: requests taken from
// TaskLinks::sdo_requests run on the master's cyclic mailbox channel and come back on sdo_results;
// a segmented upload and a segmented download run with the heap guard counting (0 allocations) and
// no joint missing a cycle; downloads of objects in the RxPDO/TxPDO and of the PDO mapping and
// assignment are refused with their reason; a second request while one is in flight is refused
// busy (the first still answered); a joint behind a cut cable is refused unreachable; a slave
// addressed by its position is reached like its joint, a junction answers that it has no mailbox and
// is refused unreachable once lost; an SDO Information request (ctl sdos) runs the same way without
// heap and carries the response's whole length; answers the result queue cannot take wait and are
// delivered in order, none lost.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/app/tasks/sdo_relay.hpp"
#include "core/memory/heap_guard.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::app {
namespace {

using protocol::SdoStatus;

class SdoRelayOnTheRobot : public ::testing::Test {
 protected:
  void SetUp() override {
    fw = std::make_unique<SimulatedFirmware>(dir.path);
    ASSERT_TRUE(fw->start_enabled());
  }
  static SdoLinkRequest request(std::uint32_t id, const char* joint, std::uint16_t index, std::uint8_t sub) {
    SdoLinkRequest r;
    r.id = id;
    r.sdo.joint = static_cast<std::uint8_t>(joint_index_by_name(joint));
    r.sdo.index = index;
    r.sdo.subindex = sub;
    return r;
  }
  static SdoLinkRequest at(std::uint32_t id, std::size_t position, std::uint16_t index, std::uint8_t sub) {
    SdoLinkRequest r;
    r.id = id;
    r.sdo.target = protocol::SdoTarget::slave;
    r.sdo.slave = static_cast<std::uint8_t>(position);
    r.sdo.index = index;
    r.sdo.subindex = sub;
    return r;
  }
  static SdoLinkRequest download(std::uint32_t id, const char* joint, std::uint16_t index, std::uint8_t sub,
                                 const std::string& bytes) {
    SdoLinkRequest r = request(id, joint, index, sub);
    r.download = true;
    std::memcpy(r.sdo.data.data(), bytes.data(), bytes.size());
    r.sdo.size = static_cast<std::uint16_t>(bytes.size());
    return r;
  }
  // Periods until `count` results arrived (or `max` periods), appended to `out` (reserved by the
  // caller: the heap-free test allocates nothing of its own either).
  void collect(std::vector<SdoLinkResult>& out, std::size_t count, int max = 2000) {
    const std::size_t until = out.size() + count;
    for (int i = 0; i < max && out.size() < until; ++i) {
      (void)fw->period();
      SdoLinkResult r;
      while (fw->links->sdo_results.try_pop(r)) out.push_back(r);
    }
  }
  std::vector<SdoLinkResult> results(std::size_t count, int max = 2000) {
    std::vector<SdoLinkResult> out;
    collect(out, count, max);
    return out;
  }
  static std::string text_of(const SdoLinkResult& r) {
    return std::string(reinterpret_cast<const char*>(r.result.data.data()), r.result.size);
  }

  testing::TempStateDir dir;
  std::unique_ptr<SimulatedFirmware> fw;
};

TEST_F(SdoRelayOnTheRobot, SegmentedTransfersRunInTheCycleWithoutHeapOrAMissedCycle) {
  const std::string label = "l_elbow drive: replaced 2026-11-26 after the stairs trial; harness B7 re-crimped; encoder offset "
                            "checked on the jig (0.01 deg); next service at 500 h";
  ASSERT_GT(label.size(), drivers::kJointMailboxSize);
  std::vector<SdoLinkResult> got;
  got.reserve(8);
  const SdoLinkRequest upload_version = request(1, "l_elbow", 0x100A, 0);
  const SdoLinkRequest write_label = download(2, "l_elbow", 0x2010, 0, label);
  const SdoLinkRequest read_label = request(3, "l_elbow", 0x2010, 0);
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::count);
  const bool pushed1 = fw->links->sdo_requests.try_push(upload_version);
  collect(got, 1);
  const bool pushed2 = fw->links->sdo_requests.try_push(write_label);
  collect(got, 1);
  const bool pushed3 = fw->links->sdo_requests.try_push(read_label);
  collect(got, 1);
  const HeapGuardCounters heap = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(heap.allocations, 0U) << "the handler's SDO path allocates nothing";
  ASSERT_TRUE(pushed1 && pushed2 && pushed3);
  ASSERT_EQ(got.size(), 3U);
  const std::vector<SdoLinkResult> first(got.begin(), got.begin() + 1);
  const std::vector<SdoLinkResult> second(got.begin() + 1, got.begin() + 2);
  const std::vector<SdoLinkResult> third(got.begin() + 2, got.begin() + 3);

  ASSERT_EQ(first.size(), 1U);
  EXPECT_EQ(first[0].id, 1U);
  EXPECT_EQ(first[0].result.status, SdoStatus::ok);
  EXPECT_EQ(first[0].result.flags, protocol::kSdoSegmented);
  EXPECT_EQ(text_of(first[0]), drivers::kJointDriveFirmwareVersion);
  ASSERT_EQ(second.size(), 1U);
  EXPECT_EQ(second[0].result.status, SdoStatus::ok);
  EXPECT_EQ(second[0].result.flags, protocol::kSdoSegmented);
  ASSERT_EQ(third.size(), 1U);
  EXPECT_EQ(text_of(third[0]), label);
  EXPECT_EQ(fw->handler->missed_cycles(kAllJoints), 0U) << "no joint lost a cycle to the SDO traffic";
  EXPECT_EQ(fw->handler->frames_missing(), 0U);
}

TEST_F(SdoRelayOnTheRobot, WritesThatFightTheCyclicImageAreRefusedWithTheirReason) {
  const std::string four(4, '\0');
  const std::string two(2, '\0');
  const std::string one(1, '\0');
  ASSERT_TRUE(fw->links->sdo_requests.try_push(download(1, "r_elbow", 0x607A, 0, four)));  // target position: RxPDO
  ASSERT_TRUE(fw->links->sdo_requests.try_push(download(2, "r_elbow", 0x6041, 0, two)));   // statusword: TxPDO
  std::vector<SdoLinkResult> got = results(2);
  ASSERT_TRUE(fw->links->sdo_requests.try_push(download(3, "r_elbow", 0x1A00, 1, four)));  // mapping in OP
  ASSERT_TRUE(fw->links->sdo_requests.try_push(download(4, "r_elbow", 0x1C12, 0, one)));   // assignment in OP
  const std::vector<SdoLinkResult> more = results(2);
  got.insert(got.end(), more.begin(), more.end());
  ASSERT_TRUE(fw->links->sdo_requests.try_push(request(5, "r_elbow", 0x607A, 0)));  // reading it is fine
  const std::vector<SdoLinkResult> read = results(1);
  ASSERT_EQ(got.size(), 4U);
  EXPECT_EQ(got[0].result.status, SdoStatus::mapped_object);
  EXPECT_EQ(got[1].result.status, SdoStatus::mapped_object);
  EXPECT_EQ(got[2].result.status, SdoStatus::pdo_configuration);
  EXPECT_EQ(got[2].result.al_state, 8U);
  EXPECT_EQ(got[3].result.status, SdoStatus::pdo_configuration);
  for (const SdoLinkResult& r : got) EXPECT_EQ(r.result.exchanges, 0U) << "nothing reached the drive";
  ASSERT_EQ(read.size(), 1U);
  EXPECT_EQ(read[0].result.status, SdoStatus::ok);
  EXPECT_EQ(read[0].result.size, 4U);

  describe_sdo_result(got[0].result);
  EXPECT_STREQ(got[0].result.text.data(), "0x607A:00 is in the RxPDO: the cyclic image writes it");
  describe_sdo_result(got[1].result);
  EXPECT_STREQ(got[1].result.text.data(), "0x6041:00 is in the TxPDO: the cyclic image writes it");
  describe_sdo_result(got[2].result);
  EXPECT_STREQ(got[2].result.text.data(), "PDO mapping is fixed while the slave is in OP");
  // The same objects outside SAFE-OP/OP, and an ordinary object: nothing to refuse.
  EXPECT_EQ(judge_sdo_download(0x1A00, 1, false), SdoStatus::ok);
  EXPECT_EQ(judge_sdo_download(0x1C13, 0, true), SdoStatus::pdo_configuration);
  EXPECT_EQ(judge_sdo_download(0x17FF, 0, true), SdoStatus::pdo_configuration);
  EXPECT_EQ(judge_sdo_download(0x6065, 0, true), SdoStatus::ok);
  EXPECT_EQ(judge_sdo_download(0x6040, 0, false), SdoStatus::mapped_object);
}

TEST_F(SdoRelayOnTheRobot, ASecondRequestInFlightIsRefusedBusyAndTheFirstStillAnswered) {
  ASSERT_TRUE(fw->links->sdo_requests.try_push(request(1, "neck_pan", 0x100A, 0)));
  ASSERT_TRUE(fw->links->sdo_requests.try_push(request(2, "neck_pan", 0x1008, 0)));
  const std::vector<SdoLinkResult> got = results(2);
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[0].id, 2U);
  EXPECT_EQ(got[0].result.status, SdoStatus::busy);
  EXPECT_EQ(got[1].id, 1U);
  EXPECT_EQ(got[1].result.status, SdoStatus::ok);
  EXPECT_EQ(text_of(got[1]), drivers::kJointDriveFirmwareVersion);
}

TEST_F(SdoRelayOnTheRobot, AJointBehindACutCableIsRefusedUnreachable) {
  ASSERT_TRUE(fw->rig->segment.cut_link(slave_position_of_joint(joint_index_by_name("l_elbow"))).ok());
  for (int i = 0; i < 50; ++i) (void)fw->period();
  ASSERT_TRUE(fw->links->sdo_requests.try_push(request(1, "l_hand", 0x603F, 0)));
  ASSERT_TRUE(fw->links->sdo_requests.try_push(request(2, "r_hand", 0x603F, 0)));
  const std::vector<SdoLinkResult> got = results(2);
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[0].result.status, SdoStatus::unreachable);
  EXPECT_EQ(got[0].result.exchanges, 0U);
  EXPECT_EQ(got[1].result.status, SdoStatus::ok);
}

// ctl sdos: an SDO Information request rides the same queue and mailbox channel (info_op set),
// without heap; its result carries the window of the response's data and the whole length; a
// junction has no mailbox, as for an upload.
TEST_F(SdoRelayOnTheRobot, SdoInformationRequestsRunInTheCycleWithoutHeapAndCarryTheWholeLength) {
  SdoLinkRequest list = request(1, "l_elbow", 1, 0);  // Get OD List, list type 1: every object
  list.info_op = protocol::SdoInfoOp::od_list;
  SdoLinkRequest window = list;
  window.id = 2;
  window.info_offset = 10;
  std::vector<SdoLinkResult> got;
  got.reserve(4);
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::count);
  const bool pushed1 = fw->links->sdo_requests.try_push(list);
  collect(got, 1);
  const bool pushed2 = fw->links->sdo_requests.try_push(window);
  collect(got, 1);
  const HeapGuardCounters heap = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(heap.allocations, 0U);
  ASSERT_TRUE(pushed1 && pushed2);
  ASSERT_EQ(got.size(), 2U);
  const protocol::SdoResultPayload& whole = got[0].result;
  EXPECT_EQ(whole.request_type, protocol::MessageType::sdo_info);
  ASSERT_EQ(whole.status, SdoStatus::ok);
  EXPECT_EQ(whole.info_total, whole.size);
  EXPECT_EQ(whole.size % 2U, 0U);
  EXPECT_GT(whole.size, 2U);
  EXPECT_EQ(whole.data[0], 1U) << "the list type first";
  EXPECT_EQ(whole.data[2], 0x00U);
  EXPECT_EQ(whole.data[3], 0x10U) << "then 0x1000";
  const protocol::SdoResultPayload& part = got[1].result;
  ASSERT_EQ(part.status, SdoStatus::ok);
  EXPECT_EQ(part.info_total, whole.info_total);
  ASSERT_EQ(part.size, whole.size - 10U);
  EXPECT_EQ(std::memcmp(part.data.data(), whole.data.data() + 10, part.size), 0);

  SdoLinkRequest junction = at(3, 0, 0x1000, 0);
  junction.info_op = protocol::SdoInfoOp::object_description;
  ASSERT_TRUE(fw->links->sdo_requests.try_push(junction));
  const std::vector<SdoLinkResult> refused = results(1);
  ASSERT_EQ(refused.size(), 1U);
  EXPECT_EQ(refused[0].result.status, SdoStatus::no_mailbox);
  EXPECT_EQ(refused[0].result.request_type, protocol::MessageType::sdo_info);
}

TEST_F(SdoRelayOnTheRobot, ASlaveByPositionIsReachedLikeItsJointAndAJunctionHasNoMailbox) {
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  ASSERT_TRUE(fw->links->sdo_requests.try_push(at(1, elbow, 0x1008, 0)));
  std::vector<SdoLinkResult> got = results(1);
  ASSERT_TRUE(fw->links->sdo_requests.try_push(at(2, 0, 0x1018, 1)));  // junction_a
  const std::vector<SdoLinkResult> junction = results(1);
  SdoLinkRequest mapped = at(3, elbow, 0x607A, 0);  // the RxPDO's target position, by position too
  mapped.download = true;
  mapped.sdo.size = 4;
  ASSERT_TRUE(fw->links->sdo_requests.try_push(mapped));
  const std::vector<SdoLinkResult> refused = results(1);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].result.status, SdoStatus::ok);
  EXPECT_EQ(text_of(got[0]), "RM-JD402");
  EXPECT_EQ(got[0].result.target, protocol::SdoTarget::slave);
  EXPECT_EQ(got[0].result.slave, elbow);
  ASSERT_EQ(junction.size(), 1U);
  EXPECT_EQ(junction[0].result.status, SdoStatus::no_mailbox);
  EXPECT_EQ(junction[0].result.slave, 0U);
  ASSERT_EQ(refused.size(), 1U);
  EXPECT_EQ(refused[0].result.status, SdoStatus::mapped_object);

  ASSERT_TRUE(fw->rig->segment.cut_link(1).ok());  // junction_b and everything behind it
  for (int i = 0; i < 50; ++i) (void)fw->period();
  ASSERT_TRUE(fw->links->sdo_requests.try_push(at(4, 1, 0x1018, 1)));
  got = results(1);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].result.status, SdoStatus::unreachable);
  describe_sdo_result(got[0].result);
  EXPECT_STREQ(got[0].result.text.data(), "the slave is lost or out of the exchange");
}

TEST_F(SdoRelayOnTheRobot, AnswersTheResultQueueCannotTakeWaitAndAreDeliveredInOrder) {
  const std::string four(4, '\0');
  for (std::uint32_t id = 1; id <= 4; ++id) {
    while (!fw->links->sdo_requests.try_push(download(id, "waist_yaw", 0x607A, 0, four))) (void)fw->period();
  }
  for (int i = 0; i < 10; ++i) (void)fw->period();  // nobody takes the results meanwhile
  std::vector<std::uint32_t> ids;
  for (int i = 0; i < 10; ++i) {
    SdoLinkResult r;
    while (fw->links->sdo_results.try_pop(r)) ids.push_back(r.id);
    (void)fw->period();
  }
  // The queue holds 2, the relay keeps one waiting and takes no new request meanwhile: none lost.
  EXPECT_EQ(ids, (std::vector<std::uint32_t>{1, 2, 3, 4}));
}

}  // namespace
}  // namespace rescue::app
