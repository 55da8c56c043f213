// SDO complete access on the drives' object dictionary, as SOEM's ec_readPDOmapCA uses it once the
// SII announces it: whole objects from subindex 0 (the count padded to 16 bits, as the LAN9252 in
// captures/soem-single-lan9252.pcapng answers 0x1C00 with 04 00 01 02 03 04) or 1, uploads as
// normal transfers with the complete-access bit mirrored (0x51), downloads in CiA 301's order
// through the same checks as single writes, refused writes leaving the object as it was.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "core/base/endian.hpp"
#include "drivers/sim/coe/coe_sdo_server.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/mailbox.hpp"

namespace rescue::drivers {
namespace {

namespace coe = ecat::coe;
namespace mbx = ecat::mbx;
using ecat::reg::AlState;

constexpr std::size_t kCommandAt = mbx::kHeaderSize + coe::kCoeHeaderSize;

class CompleteAccess : public testing::Test {
 protected:
  CompleteAccess() : objects_(joint_index_by_name("l_leg"), slave_position_of_joint(joint_index_by_name("l_leg"))) {}

  coe::Message exchange(const coe::Sdo& sdo, AlState state = AlState::pre_op) {
    std::array<std::uint8_t, 128> request{};
    mbx::Header h;
    h.counter = 1;
    EXPECT_TRUE(coe::encode(ByteSpan(request), h, sdo).ok());
    length_ = serve_sdo(ConstByteSpan(request), objects_.od(), state, ByteSpan(response_), 2);
    auto m = coe::decode(ConstByteSpan(response_.data(), length_));
    EXPECT_TRUE(m.ok());
    return m.ok() ? m.value() : coe::Message{};
  }
  std::vector<std::uint8_t> upload(std::uint16_t index, std::uint8_t sub) {
    const coe::Message m = exchange(coe::upload_request(index, sub, true));
    EXPECT_EQ(m.sdo.kind, coe::SdoKind::upload_initiate_response) << std::hex << index << " abort " << m.sdo.abort_code;
    EXPECT_EQ(response_[kCommandAt], 0x51) << std::hex << index;  // normal, size indicated, complete access
    EXPECT_TRUE(m.sdo.complete_access);
    EXPECT_EQ(m.sdo.size, m.sdo.data.size());
    return std::vector<std::uint8_t>(m.sdo.data.begin(), m.sdo.data.end());
  }
  // A complete-access download as SOEM sends it (0x31: normal transfer, size indicated).
  coe::Message download(std::uint16_t index, std::uint8_t sub, const std::vector<std::uint8_t>& data,
                        AlState state = AlState::pre_op) {
    coe::Sdo sdo = coe::download_request(index, sub, ConstByteSpan(data.data(), data.size()));
    sdo.expedited = false;
    sdo.size_indicated = true;
    sdo.size = static_cast<std::uint32_t>(data.size());
    sdo.complete_access = true;
    return exchange(sdo, state);
  }
  std::uint32_t abort_of(const coe::Message& m) {
    EXPECT_EQ(m.sdo.kind, coe::SdoKind::abort);
    return m.sdo.abort_code;
  }
  static std::vector<std::uint8_t> words32(std::uint16_t count, const std::vector<std::uint32_t>& values) {
    std::vector<std::uint8_t> v{static_cast<std::uint8_t>(count), 0};
    for (std::uint32_t x : values) {
      for (int i = 0; i < 4; ++i) v.push_back(static_cast<std::uint8_t>(x >> (8 * i)));
    }
    return v;
  }

  JointDriveObjects objects_;
  std::array<std::uint8_t, 128> response_{};
  std::size_t length_{0};
};

TEST_F(CompleteAccess, UploadsGiveTheCountPaddedTo16BitsThenEveryEntry) {
  EXPECT_EQ(upload(0x1C00, 0), (std::vector<std::uint8_t>{4, 0, 1, 2, 3, 4}));
  EXPECT_EQ(upload(0x1C12, 0), (std::vector<std::uint8_t>{1, 0, 0x00, 0x16}));
  EXPECT_EQ(upload(0x1C13, 0), (std::vector<std::uint8_t>{1, 0, 0x00, 0x1A}));
  std::vector<std::uint32_t> rx;
  for (const PdoMappingEntry& e : kJointRxMapping) rx.push_back(e.mapping_word());
  EXPECT_EQ(upload(0x1600, 0), words32(static_cast<std::uint16_t>(rx.size()), rx));
  // From subindex 1: the entries without the count.
  const auto from1 = upload(0x1600, 1);
  const auto from0 = words32(static_cast<std::uint16_t>(rx.size()), rx);
  EXPECT_EQ(from1, std::vector<std::uint8_t>(from0.begin() + 2, from0.end()));
  // An object without subindexes: its value.
  EXPECT_EQ(upload(0x6502, 0).size(), 4u);
}

TEST_F(CompleteAccess, TheMappingSizesAMasterAddsUpMatchTheProcessData) {
  // SOEM's ec_readPDOmapCA: SM types from 0x1C00, the assigned PDOs, their entries' bit lengths.
  const auto types = upload(0x1C00, 0);
  unsigned output_bits = 0;
  unsigned input_bits = 0;
  for (std::size_t sm = 2; sm < types[0]; ++sm) {
    const auto assigned = upload(static_cast<std::uint16_t>(0x1C10 + sm), 0);
    for (std::size_t k = 0; k < assigned[0]; ++k) {
      const auto pdo = upload(load_le16(assigned.data() + 2 + 2 * k), 0);
      for (std::size_t e = 0; e < pdo[0]; ++e) {
        const unsigned bits = pdo[2 + 4 * e];
        (types[2 + sm] == 3 ? output_bits : input_bits) += bits;
      }
    }
  }
  EXPECT_EQ(output_bits, kJointOutputBytes * 8);
  EXPECT_EQ(input_bits, kJointInputBytes * 8);
}

TEST_F(CompleteAccess, DownloadInPreOpWritesTheWholeObjectThroughTheUsualChecks) {
  coe::Message m = download(0x1C12, 0, {1, 0, 0x00, 0x16});
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::download_initiate_response);
  EXPECT_EQ(objects_.od().get_u32(0x1C12, 0), 1u);
  EXPECT_EQ(objects_.od().get_u32(0x1C12, 1), 0x1600u);

  std::vector<std::uint32_t> tx;
  for (const PdoMappingEntry& e : kJointTxMapping) tx.push_back(e.mapping_word());
  m = download(0x1A00, 0, words32(static_cast<std::uint16_t>(tx.size()), tx));
  EXPECT_EQ(m.sdo.kind, coe::SdoKind::download_initiate_response);
  EXPECT_EQ(objects_.od().get_u32(0x1A00, 0), tx.size());
}

TEST_F(CompleteAccess, RefusedDownloadsLeaveTheObjectAsItWas) {
  // Another PDO than the drive's: the device's check refuses the entry; count and entry restored.
  EXPECT_EQ(abort_of(download(0x1C12, 0, {1, 0, 0x01, 0x16})), coe::abort_code::kValueRange);
  EXPECT_EQ(objects_.od().get_u32(0x1C12, 0), 1u);
  EXPECT_EQ(objects_.od().get_u32(0x1C12, 1), 0x1600u);
  // Not in PRE-OP.
  EXPECT_EQ(abort_of(download(0x1C12, 0, {1, 0, 0x00, 0x16}, AlState::safe_op)), coe::abort_code::kCannotTransferInState);
  EXPECT_EQ(objects_.od().get_u32(0x1C12, 0), 1u);
  // Lengths that do not match the count.
  EXPECT_EQ(abort_of(download(0x1C12, 0, {1, 0, 0x00})), coe::abort_code::kLengthTooLow);
  EXPECT_EQ(abort_of(download(0x1C12, 0, {1, 0, 0x00, 0x16, 0})), coe::abort_code::kLengthTooHigh);
  // More entries than the object has.
  EXPECT_EQ(abort_of(download(0x1C12, 0, {2, 0, 0x00, 0x16, 0x00, 0x16})), coe::abort_code::kValueTooHigh);
  // Read-only objects stay read-only.
  EXPECT_EQ(abort_of(download(0x1C00, 0, {4, 0, 1, 2, 3, 4})), coe::abort_code::kReadOnly);
  EXPECT_EQ(objects_.od().get_u32(0x1C00, 0), 4u);
}

TEST_F(CompleteAccess, SubindexAboveOneAndMissingObjectsAreAborted) {
  EXPECT_EQ(abort_of(exchange(coe::upload_request(0x1600, 2, true))), coe::abort_code::kUnsupportedAccess);
  EXPECT_EQ(abort_of(exchange(coe::upload_request(0x2000, 0, true))), coe::abort_code::kObjectDoesNotExist);
  EXPECT_EQ(abort_of(exchange(coe::upload_request(0x6041, 1, true))), coe::abort_code::kSubindexDoesNotExist);
}

}  // namespace
}  // namespace rescue::drivers
