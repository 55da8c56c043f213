// The drives' CoE SDO Information service (ETG.1000.6 5.6.3), request bytes in and response bytes
// out through the SDO server, as a master that lists the object dictionary sees it (SOEM's
// `slaveinfo -sdo`): the OD list and its five list lengths, PDO-mappable lists that match the
// mapping objects, object descriptions (VAR / ARRAY / RECORD, CiA 301 types), entry descriptions
// (type, bit length, access and mapping bits, name), fragments when SM1 is short, and the errors.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "core/base/endian.hpp"
#include "drivers/sim/coe/coe_sdo_information.hpp"
#include "drivers/sim/coe/coe_sdo_server.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "ecat/mailbox/mailbox.hpp"

namespace rescue::drivers {
namespace {

namespace mbx = ecat::mbx;
using ecat::reg::AlState;

constexpr std::size_t kInfoDataAt = 12;  // mailbox header 6, CoE header 2, opcode, reserved, fragments 2

struct Answer {
  std::uint8_t opcode{0};
  bool incomplete{false};
  std::uint16_t fragments_left{0};
  std::vector<std::uint8_t> data;
};

class SdoInformation : public testing::Test {
 protected:
  SdoInformation() : objects_(joint_index_by_name("r_elbow"), slave_position_of_joint(joint_index_by_name("r_elbow"))) {}

  // The request as a master writes it into SM0: opcode and its data after the three headers.
  std::vector<std::uint8_t> request(std::uint8_t opcode, std::vector<std::uint8_t> data) const {
    std::vector<std::uint8_t> r(128, 0);
    const auto length = static_cast<std::uint16_t>(2 + 4 + data.size());
    store_le16(r.data(), length);
    r[5] = 0x13;  // counter 1, CoE
    store_le16(r.data() + 6, 0x8000);  // service 8: SDO information
    r[8] = opcode;
    for (std::size_t i = 0; i < data.size(); ++i) r[kInfoDataAt + i] = data[i];
    return r;
  }

  Answer decode(std::size_t n) const {
    Answer a;
    EXPECT_GE(n, kInfoDataAt);
    if (n < kInfoDataAt) return a;
    EXPECT_EQ(load_le16(response_.data()), n - mbx::kHeaderSize);  // mailbox length
    EXPECT_EQ(response_[5] & 0x0F, 0x03);                          // CoE
    EXPECT_EQ(load_le16(response_.data() + 6), 0x8000);
    a.opcode = static_cast<std::uint8_t>(response_[8] & 0x7F);
    a.incomplete = (response_[8] & 0x80) != 0;
    a.fragments_left = load_le16(response_.data() + 10);
    a.data.assign(response_.begin() + kInfoDataAt, response_.begin() + static_cast<std::ptrdiff_t>(n));
    return a;
  }

  Answer ask(std::uint8_t opcode, std::vector<std::uint8_t> data, std::size_t sm1 = 128) {
    const auto r = request(opcode, std::move(data));
    return decode(serve_sdo(ConstByteSpan(r.data(), r.size()), objects_.od(), AlState::pre_op,
                            ByteSpan(response_.data(), sm1), 5));
  }

  static std::vector<std::uint16_t> words(const std::vector<std::uint8_t>& bytes) {
    std::vector<std::uint16_t> w;
    for (std::size_t i = 0; i + 1 < bytes.size(); i += 2) w.push_back(load_le16(bytes.data() + i));
    return w;
  }
  static std::vector<std::uint8_t> le16(std::uint16_t v) { return {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8)}; }
  static std::string text(const std::vector<std::uint8_t>& data, std::size_t from) {
    return std::string(data.begin() + static_cast<std::ptrdiff_t>(from), data.end());
  }

  // Every distinct index of the dictionary, in table order (ascending).
  std::vector<std::uint16_t> all_indexes() const {
    std::vector<std::uint16_t> v;
    for (const ObjectEntry& e : objects_.od().entries()) {
      if (v.empty() || v.back() != e.index) v.push_back(e.index);
    }
    return v;
  }

  JointDriveObjects objects_;
  std::array<std::uint8_t, 128> response_{};
};

TEST_F(SdoInformation, OdListOfAllObjectsGivesEveryIndexAscendingInOneMessage) {
  const Answer a = ask(sdo_info::kGetOdListRequest, le16(1));
  EXPECT_EQ(a.opcode, sdo_info::kGetOdListResponse);
  EXPECT_FALSE(a.incomplete);
  EXPECT_EQ(a.fragments_left, 0);
  const auto w = words(a.data);
  ASSERT_FALSE(w.empty());
  EXPECT_EQ(w[0], 1);  // the list type comes back first
  const std::vector<std::uint16_t> indexes(w.begin() + 1, w.end());
  EXPECT_EQ(indexes, all_indexes());
  EXPECT_EQ(indexes.front(), 0x1000);
  EXPECT_EQ(indexes.back(), 0x6502);
}

TEST_F(SdoInformation, ListLengthsAndPdoMappableListsFollowTheMappingObjects) {
  const auto lengths = words(ask(sdo_info::kGetOdListRequest, le16(0)).data);
  ASSERT_EQ(lengths.size(), 6u);
  EXPECT_EQ(lengths[0], 0);                   // list type 0
  EXPECT_EQ(lengths[1], all_indexes().size());
  EXPECT_EQ(lengths[2], 5);                   // RxPDO-mappable: what 0x1600 maps
  EXPECT_EQ(lengths[3], 6);                   // TxPDO-mappable: what 0x1A00 maps
  EXPECT_EQ(lengths[4], 0);                   // no backup objects
  EXPECT_EQ(lengths[5], 0);                   // no startup parameters

  const auto rx = words(ask(sdo_info::kGetOdListRequest, le16(2)).data);
  EXPECT_EQ(rx, (std::vector<std::uint16_t>{2, 0x6040, 0x6060, 0x6071, 0x607A, 0x60FF}));
  const auto tx = words(ask(sdo_info::kGetOdListRequest, le16(3)).data);
  EXPECT_EQ(tx, (std::vector<std::uint16_t>{3, 0x603F, 0x6041, 0x6061, 0x6064, 0x606C, 0x6077}));
}

TEST_F(SdoInformation, AShortMailboxCutsTheOdListIntoFragmentsThatJoinUp) {
  // SM1 of 40 bytes: 28 data bytes per fragment, 14 words; 1 + all indexes words in all.
  constexpr std::size_t kSm1 = 40;
  const auto r = request(sdo_info::kGetOdListRequest, le16(1));
  const std::size_t total_words = 1 + all_indexes().size();
  const std::size_t expected_fragments = (total_words + 13) / 14;
  ASSERT_GT(expected_fragments, 1u);
  std::vector<std::uint16_t> joined;
  for (std::uint16_t k = 0; k < expected_fragments; ++k) {
    const std::size_t n = k == 0 ? serve_sdo(ConstByteSpan(r.data(), r.size()), objects_.od(), AlState::pre_op,
                                             ByteSpan(response_.data(), kSm1), 5)
                                 : serve_sdo_fragment(ConstByteSpan(r.data(), r.size()), objects_.od(),
                                                      ByteSpan(response_.data(), kSm1), 5, k);
    ASSERT_GT(n, 0u) << "fragment " << k;
    ASSERT_LE(n, kSm1);
    const Answer a = decode(n);
    EXPECT_EQ(a.opcode, sdo_info::kGetOdListResponse);
    EXPECT_EQ(a.fragments_left, expected_fragments - 1 - k);
    EXPECT_EQ(a.incomplete, a.fragments_left != 0);
    const auto w = words(a.data);
    joined.insert(joined.end(), w.begin(), w.end());
  }
  EXPECT_EQ(serve_sdo_fragment(ConstByteSpan(r.data(), r.size()), objects_.od(), ByteSpan(response_.data(), kSm1), 5,
                               static_cast<std::uint16_t>(expected_fragments)),
            0u);
  ASSERT_EQ(joined.size(), total_words);
  EXPECT_EQ(joined[0], 1);
  EXPECT_EQ(std::vector<std::uint16_t>(joined.begin() + 1, joined.end()), all_indexes());
}

TEST_F(SdoInformation, ObjectDescriptionsGiveCodeTypeHighestSubindexAndName) {
  struct Expected {
    std::uint16_t index;
    std::uint16_t type;
    std::uint8_t max_sub;
    std::uint8_t code;
    const char* name;
  };
  const Expected cases[] = {
      {0x6040, 0x0006, 0, sdo_info::kObjectCodeVar, "Controlword"},
      {0x1008, 0x0009, 0, sdo_info::kObjectCodeVar, "Manufacturer device name"},
      {0x1018, 0x0023, 4, sdo_info::kObjectCodeRecord, "Identity"},
      {0x1600, 0x0021, 5, sdo_info::kObjectCodeRecord, "RxPDO mapping"},
      {0x1A00, 0x0021, 6, sdo_info::kObjectCodeRecord, "TxPDO mapping"},
      {0x1C00, 0x0005, 4, sdo_info::kObjectCodeArray, "SyncManager types"},
      {0x1C12, 0x0006, 1, sdo_info::kObjectCodeArray, "RxPDO assignment"},
      {0x607D, 0x0004, 2, sdo_info::kObjectCodeArray, "Software position limit"},
  };
  for (const Expected& c : cases) {
    const Answer a = ask(sdo_info::kGetObjectDescriptionRequest, le16(c.index));
    EXPECT_EQ(a.opcode, sdo_info::kGetObjectDescriptionResponse) << std::hex << c.index;
    ASSERT_GE(a.data.size(), 6u);
    EXPECT_EQ(load_le16(a.data.data()), c.index);
    EXPECT_EQ(load_le16(a.data.data() + 2), c.type) << std::hex << c.index;
    EXPECT_EQ(a.data[4], c.max_sub) << std::hex << c.index;
    EXPECT_EQ(a.data[5], c.code) << std::hex << c.index;
    EXPECT_EQ(text(a.data, 6), c.name);
  }
}

TEST_F(SdoInformation, EntryDescriptionsGiveTypeBitLengthAccessAndMappingBits) {
  struct Expected {
    std::uint16_t index;
    std::uint8_t sub;
    std::uint16_t type;
    std::uint16_t bits;
    std::uint16_t access;
    const char* name;
  };
  const Expected cases[] = {
      {0x6040, 0, 0x0006, 16, 0x007F, "Controlword"},         // read + write always, RxPDO-mappable
      {0x6041, 0, 0x0006, 16, 0x0087, "Statusword"},          // read only, TxPDO-mappable
      {0x607A, 0, 0x0004, 32, 0x007F, "Target position"},
      {0x6065, 0, 0x0007, 32, 0x003F, "Following error window"},  // not mapped
      {0x1C12, 1, 0x0006, 16, 0x000F, "RxPDO assigned"},      // writable in PRE-OP only
      {0x1018, 1, 0x0007, 32, 0x0007, "Vendor ID"},
      {0x1008, 0, 0x0009, static_cast<std::uint16_t>(kDeviceNameCapacity * 8), 0x0007, "Manufacturer device name"},
  };
  for (const Expected& c : cases) {
    const Answer a = ask(sdo_info::kGetEntryDescriptionRequest, {static_cast<std::uint8_t>(c.index),
                                                                 static_cast<std::uint8_t>(c.index >> 8), c.sub, 0x07});
    EXPECT_EQ(a.opcode, sdo_info::kGetEntryDescriptionResponse) << std::hex << c.index;
    ASSERT_GE(a.data.size(), 10u);
    EXPECT_EQ(load_le16(a.data.data()), c.index);
    EXPECT_EQ(a.data[2], c.sub);
    EXPECT_EQ(a.data[3], 0);  // value info: no unit, default, minimum or maximum follow
    EXPECT_EQ(load_le16(a.data.data() + 4), c.type) << std::hex << c.index;
    EXPECT_EQ(load_le16(a.data.data() + 6), c.bits) << std::hex << c.index;
    EXPECT_EQ(load_le16(a.data.data() + 8), c.access) << std::hex << c.index;
    EXPECT_EQ(text(a.data, 10), c.name);
  }
}

TEST_F(SdoInformation, MissingObjectsSubindexesAndUnknownOpcodesGetAnSdoInfoError) {
  auto error_of = [](const Answer& a) {
    EXPECT_EQ(a.opcode, sdo_info::kErrorRequest);
    return a.data.size() >= 4 ? load_le32(a.data.data()) : 0u;
  };
  EXPECT_EQ(error_of(ask(sdo_info::kGetObjectDescriptionRequest, le16(0x2000))), 0x06020000u);
  EXPECT_EQ(error_of(ask(sdo_info::kGetEntryDescriptionRequest, {0x00, 0x20, 0, 0x07})), 0x06020000u);
  EXPECT_EQ(error_of(ask(sdo_info::kGetEntryDescriptionRequest, {0x18, 0x10, 9, 0x07})), 0x06090011u);
  EXPECT_EQ(error_of(ask(0x09, {})), 0x05040001u);               // no such opcode
  EXPECT_EQ(error_of(ask(sdo_info::kGetOdListRequest, le16(6))), 0x06010000u);  // no such list
}

TEST_F(SdoInformation, ARequestTooShortForItsOpcodeGetsAMailboxError) {
  auto r = request(sdo_info::kGetEntryDescriptionRequest, {});
  store_le16(r.data(), 2 + 4 + 2);  // index only, no subindex
  const std::size_t n = serve_sdo(ConstByteSpan(r.data(), r.size()), objects_.od(), AlState::pre_op, ByteSpan(response_), 5);
  auto m = mbx::decode(ConstByteSpan(response_.data(), n));
  ASSERT_TRUE(m.ok());
  auto detail = mbx::decode_error_reply(m.value());
  ASSERT_TRUE(detail.ok());
  EXPECT_EQ(detail.value(), mbx::error_code::kSizeTooShort);
}

}  // namespace
}  // namespace rescue::drivers
