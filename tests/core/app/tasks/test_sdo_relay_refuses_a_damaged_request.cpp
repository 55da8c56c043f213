// The socket handler's SDO request is a record of the shared segment (TaskLinks::sdo_requests). A
// request with a field the socket handler never writes is damage (a stray write, a bit flip): the
// EtherCAT handler's SdoRelay refuses it whole and counts it, sends nothing to any slave and answers
// nothing (its id is not trusted; the socket handler's own limit answers the operator). Before, a
// size of 300 was clamped to 256 bytes and written, an unknown target was taken as a joint, and an
// unknown SDO Information opcode was sent to the slave. A whole request after them runs as before.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "core/app/tasks/sdo_relay.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::app {
namespace {

using protocol::SdoStatus;

class DamagedSdoRequest : public ::testing::Test {
 protected:
  void SetUp() override {
    fw = std::make_unique<SimulatedFirmware>(dir.path);
    ASSERT_TRUE(fw->start_enabled());
  }
  // A whole upload of the drive's firmware version from l_elbow, as the socket handler writes it.
  static SdoLinkRequest upload(std::uint32_t id) {
    SdoLinkRequest r;
    r.id = id;
    r.sdo.joint = static_cast<std::uint8_t>(joint_index_by_name("l_elbow"));
    r.sdo.index = 0x100A;
    return r;
  }
  // Pushes `r`, runs `periods` periods and returns what came back.
  std::vector<SdoLinkResult> run(const SdoLinkRequest& r, int periods = 300) {
    EXPECT_TRUE(fw->links->sdo_requests.try_push(r));
    std::vector<SdoLinkResult> out;
    for (int i = 0; i < periods; ++i) {
      (void)fw->period();
      SdoLinkResult got;
      while (fw->links->sdo_results.try_pop(got)) out.push_back(got);
    }
    return out;
  }
  const SdoRelay& relay() const { return fw->handler->sdo_relay(); }

  testing::TempStateDir dir;
  std::unique_ptr<SimulatedFirmware> fw;
};

TEST_F(DamagedSdoRequest, ADownloadLongerThanTheRecordIsRefusedNotClamped) {
  SdoLinkRequest r = upload(1);
  r.download = true;
  r.sdo.index = 0x2010;  // the drive's writable label
  r.sdo.size = 300;
  EXPECT_TRUE(run(r).empty());
  EXPECT_EQ(relay().damaged_requests(), 1U);
  EXPECT_EQ(relay().transfers(), 0U) << "nothing reached the drive";
}

TEST_F(DamagedSdoRequest, SizesAndFlagsTheSocketHandlerNeverWritesAreRefused) {
  SdoLinkRequest empty_download = upload(1);
  empty_download.download = true;  // a download of 0 bytes
  SdoLinkRequest sized_upload = upload(2);
  sized_upload.sdo.size = 4;  // an upload carries no value
  SdoLinkRequest flag = upload(3);
  const unsigned char byte = 0x80;
  std::memcpy(&flag.download, &byte, 1);  // as a stray write leaves it in the segment
  SdoLinkRequest information_download = upload(4);
  information_download.info_op = protocol::SdoInfoOp::od_list;
  information_download.download = true;
  information_download.sdo.size = 1;
  for (const SdoLinkRequest& r : {empty_download, sized_upload, flag, information_download}) EXPECT_TRUE(run(r, 50).empty());
  EXPECT_EQ(relay().damaged_requests(), 4U);
  EXPECT_EQ(relay().transfers(), 0U);
}

TEST_F(DamagedSdoRequest, AnUnknownTargetIsNotTakenForAJoint) {
  SdoLinkRequest r = upload(1);
  r.sdo.target = static_cast<protocol::SdoTarget>(7);
  EXPECT_TRUE(run(r).empty());
  EXPECT_EQ(relay().damaged_requests(), 1U);
  EXPECT_EQ(relay().transfers(), 0U);
}

TEST_F(DamagedSdoRequest, AnUnknownInformationOpcodeIsNotSentToTheSlave) {
  SdoLinkRequest r = upload(1);
  r.info_op = static_cast<protocol::SdoInfoOp>(2);
  EXPECT_TRUE(run(r).empty());
  EXPECT_EQ(relay().damaged_requests(), 1U);
  EXPECT_EQ(relay().transfers(), 0U);
}

TEST_F(DamagedSdoRequest, AWholeRequestAfterADamagedOneRunsAsBefore) {
  SdoLinkRequest bad = upload(1);
  bad.sdo.target = static_cast<protocol::SdoTarget>(0xFF);
  EXPECT_TRUE(run(bad, 5).empty());
  const std::vector<SdoLinkResult> got = run(upload(2), 2000);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].id, 2U);
  EXPECT_EQ(got[0].result.status, SdoStatus::ok);
  EXPECT_EQ(relay().damaged_requests(), 1U);
  EXPECT_EQ(relay().transfers(), 1U);
}

}  // namespace
}  // namespace rescue::app
