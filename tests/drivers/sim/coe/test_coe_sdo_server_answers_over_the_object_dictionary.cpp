// The drive's SDO server, request bytes in and response bytes out, over the joint drive's object
// dictionary: expedited and normal uploads, expedited downloads, and the abort codes a real drive
// gives (object / subindex missing, read-only, wrong length, wrong state, bad value), plus the
// mailbox error replies for what is not an SDO.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "core/base/endian.hpp"
#include "drivers/sim/coe/coe_sdo_server.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/mailbox.hpp"

namespace rescue::drivers {
namespace {

namespace coe = ecat::coe;
namespace mbx = ecat::mbx;
using ecat::reg::AlState;

class SdoServer : public testing::Test {
 protected:
  SdoServer() : objects_(joint_index_by_name("l_wrist_yaw"), slave_position_of_joint(joint_index_by_name("l_wrist_yaw"))) {}

  // Sends `sdo` as the master would (counter 1) and decodes the answer.
  coe::Message exchange(const coe::Sdo& sdo, AlState state = AlState::pre_op) {
    std::array<std::uint8_t, 128> request{};  // a whole SM0 buffer, zero padded
    mbx::Header h;
    h.counter = 1;
    EXPECT_TRUE(coe::encode(ByteSpan(request), h, sdo).ok());
    return answer(ConstByteSpan(request), state);
  }
  coe::Message answer(ConstByteSpan request, AlState state) {
    response_length_ = serve_sdo(request, objects_.od(), state, ByteSpan(response_), 3);
    auto m = coe::decode(ConstByteSpan(response_.data(), response_length_));
    EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().what);
    return m.ok() ? m.value() : coe::Message{};
  }
  std::uint32_t abort_code_of(const coe::Sdo& sdo, AlState state = AlState::pre_op) {
    const coe::Message m = exchange(sdo, state);
    EXPECT_EQ(m.sdo.kind, coe::SdoKind::abort);
    EXPECT_EQ(m.sdo.index, sdo.index);
    EXPECT_EQ(m.sdo.subindex, sdo.subindex);
    return m.sdo.abort_code;
  }
  template <typename T>
  coe::Sdo write(std::uint16_t index, std::uint8_t sub, T value) {
    static_assert(sizeof(T) <= 4, "expedited");
    for (std::size_t i = 0; i < sizeof(T); ++i) bytes_[i] = static_cast<std::uint8_t>(static_cast<std::uint32_t>(value) >> (8 * i));
    return coe::download_request(index, sub, ConstByteSpan(bytes_.data(), sizeof(T)));
  }

  JointDriveObjects objects_;
  std::array<std::uint8_t, 128> response_{};
  std::size_t response_length_{0};
  std::array<std::uint8_t, 4> bytes_{};
};

TEST_F(SdoServer, ExpeditedUploadOfIdentityAndDeviceType) {
  coe::Message m = exchange(coe::upload_request(0x1018, 1));
  EXPECT_EQ(m.mailbox.counter, 3);
  EXPECT_EQ(m.service, coe::Service::sdo_response);
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::upload_initiate_response);
  EXPECT_TRUE(m.sdo.expedited);
  ASSERT_EQ(m.sdo.data.size(), 4u);
  EXPECT_EQ(load_le32(m.sdo.data.data()), kRescueVendorId);
  m = exchange(coe::upload_request(0x1018, 0));
  ASSERT_EQ(m.sdo.data.size(), 1u);
  EXPECT_EQ(m.sdo.data[0], 4);
  m = exchange(coe::upload_request(0x1000, 0));
  EXPECT_EQ(load_le32(m.sdo.data.data()), kDeviceTypeServoDrive);
  m = exchange(coe::upload_request(0x1C12, 1));
  ASSERT_EQ(m.sdo.data.size(), 2u);
  EXPECT_EQ(load_le16(m.sdo.data.data()), 0x1600);
  m = exchange(coe::upload_request(0x1A00, 6));
  EXPECT_EQ(load_le32(m.sdo.data.data()), 0x603F0010u);
}

TEST_F(SdoServer, NormalUploadOfTheDeviceName) {
  const coe::Message m = exchange(coe::upload_request(0x1008, 0));
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::upload_initiate_response);
  EXPECT_FALSE(m.sdo.expedited);
  EXPECT_EQ(m.sdo.size, std::string(kJointDriveIdentity.name).size());
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(m.sdo.data.data()), m.sdo.data.size()), kJointDriveIdentity.name);
}

TEST_F(SdoServer, ExpeditedDownloadChangesTheObject) {
  coe::Message m = exchange(write<std::uint16_t>(0x6072, 0, 800), AlState::op);
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::download_initiate_response);
  EXPECT_EQ(m.sdo.index, 0x6072);
  EXPECT_EQ(objects_.settings().max_torque_per_mille, 800);
  m = exchange(coe::upload_request(0x6072, 0));
  EXPECT_EQ(load_le16(m.sdo.data.data()), 800);
  // A normal (non-expedited) download of 4 bytes is as good.
  coe::Sdo normal = write<std::uint32_t>(0x6065, 0, 12345);
  normal.expedited = false;
  m = exchange(normal);
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::download_initiate_response);
  EXPECT_EQ(objects_.settings().following_error_window_counts, 12345u);
}

TEST_F(SdoServer, AbortsWithTheStandardCodes) {
  EXPECT_EQ(abort_code_of(coe::upload_request(0x2000, 0)), coe::abort_code::kObjectDoesNotExist);
  EXPECT_EQ(abort_code_of(coe::upload_request(0x1018, 5)), coe::abort_code::kSubindexDoesNotExist);
  EXPECT_EQ(abort_code_of(write<std::uint32_t>(0x1018, 1, 7)), coe::abort_code::kReadOnly);
  EXPECT_EQ(abort_code_of(write<std::uint16_t>(0x6041, 0, 7)), coe::abort_code::kReadOnly);
  EXPECT_EQ(abort_code_of(write<std::uint32_t>(0x6072, 0, 800)), coe::abort_code::kLengthMismatch);  // u16 object
  EXPECT_EQ(abort_code_of(write<std::uint8_t>(0x607A, 0, 1)), coe::abort_code::kLengthMismatch);
  EXPECT_EQ(abort_code_of(write<std::uint16_t>(0x6072, 0, 1001)), coe::abort_code::kValueTooHigh);
  EXPECT_EQ(abort_code_of(write<std::int8_t>(0x6060, 0, 1)), coe::abort_code::kValueRange);  // profile position: not supported
  // Complete access: test_coe_complete_access_reads_and_writes_whole_objects.
  EXPECT_EQ(abort_code_of(coe::upload_request(0x1C12, 2, true)), coe::abort_code::kUnsupportedAccess);
}

TEST_F(SdoServer, PdoAssignmentIsWritableOnlyInPreOp) {
  for (AlState state : {AlState::safe_op, AlState::op}) {
    EXPECT_EQ(abort_code_of(write<std::uint8_t>(0x1C12, 0, 0), state), coe::abort_code::kCannotTransferInState);
    EXPECT_EQ(abort_code_of(write<std::uint8_t>(0x1600, 0, 0), state), coe::abort_code::kCannotTransferInState);
  }
  const coe::Message m = exchange(write<std::uint8_t>(0x1C12, 0, 0), AlState::pre_op);
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::download_initiate_response);
  EXPECT_FALSE(objects_.mapping_is_complete());
}

TEST_F(SdoServer, SegmentWithoutATransferAndBlockTransfersAreUnknownCommands) {
  coe::Sdo segment;
  segment.kind = coe::SdoKind::upload_segment_request;
  coe::Message m = exchange(segment);
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::abort);
  EXPECT_EQ(m.sdo.abort_code, coe::abort_code::kUnknownCommand);

  std::array<std::uint8_t, 16> block{};
  mbx::Header h;
  ASSERT_TRUE(coe::encode(ByteSpan(block), h, coe::upload_request(0x6041, 0)).ok());
  block[8] = 0xA0;  // block upload initiate
  m = answer(ConstByteSpan(block), AlState::pre_op);
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::abort);
  EXPECT_EQ(m.sdo.index, 0x6041);
  EXPECT_EQ(m.sdo.abort_code, coe::abort_code::kUnknownCommand);
}

TEST_F(SdoServer, AbortFromTheMasterIsNotAnswered) {
  std::array<std::uint8_t, 16> request{};
  ASSERT_TRUE(coe::encode(ByteSpan(request), mbx::Header{}, coe::abort(0x1008, 0, coe::abort_code::kTimeout)).ok());
  EXPECT_EQ(serve_sdo(ConstByteSpan(request), objects_.od(), AlState::pre_op, ByteSpan(response_), 1), 0u);
}

TEST_F(SdoServer, WhatIsNotAnSdoGetsAMailboxErrorReply) {
  auto error_of = [this](ConstByteSpan request) {
    const std::size_t n = serve_sdo(request, objects_.od(), AlState::pre_op, ByteSpan(response_), 1);
    auto m = mbx::decode(ConstByteSpan(response_.data(), n));
    EXPECT_TRUE(m.ok());
    auto detail = mbx::decode_error_reply(m.value());
    EXPECT_TRUE(detail.ok());
    return detail.value_or(0);
  };
  std::array<std::uint8_t, 16> eoe{10, 0, 0, 0, 0, 0x12};  // EoE
  EXPECT_EQ(error_of(ConstByteSpan(eoe)), mbx::error_code::kUnsupportedProtocol);
  std::array<std::uint8_t, 16> tx_pdo{2, 0, 0, 0, 0, 0x13, 0x00, 0x40};  // CoE TxPDO over the mailbox
  EXPECT_EQ(error_of(ConstByteSpan(tx_pdo)), mbx::error_code::kServiceNotSupported);
  std::array<std::uint8_t, 16> too_long{200, 0, 0, 0, 0, 0x13};  // length past the buffer
  EXPECT_EQ(error_of(ConstByteSpan(too_long)), mbx::error_code::kInvalidSize);
  std::array<std::uint8_t, 16> short_sdo{4, 0, 0, 0, 0, 0x13, 0x00, 0x20, 0x40, 0x41};
  EXPECT_EQ(error_of(ConstByteSpan(short_sdo)), mbx::error_code::kSizeTooShort);
}

}  // namespace
}  // namespace rescue::drivers
