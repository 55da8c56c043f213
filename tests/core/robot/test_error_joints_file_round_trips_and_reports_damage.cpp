// The error-joints file codec: a round trip keeps everything; empty, truncated, garbage, wrong-version,
// oversized, foreign and corrupt images each give a clear error, and every record that can still be
// trusted is kept (one damaged record never hides the others).
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <vector>

#include "core/base/crc32.hpp"
#include "core/base/endian.hpp"
#include "core/robot/error_joints_file.hpp"

namespace rescue {
namespace {

bool same(const LostJointRecord& a, const LostJointRecord& b) {
  return a.joint == b.joint && a.reason == b.reason && a.last_position_counts == b.last_position_counts &&
         a.time_unix_ns == b.time_unix_ns && a.cycle == b.cycle;
}

// l_elbow cut: l_elbow, l_wrist_yaw, l_wrist_pitch, l_hand, each with its own position.
ErrorJointsContents elbow_cut() {
  ErrorJointsContents c;
  c.sequence = 7;
  const JointMask lost = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));
  std::int32_t pos = -300000;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((lost & joint_bit(j)) == 0) continue;
    LostJointRecord r;
    r.joint = static_cast<std::uint8_t>(j);
    r.reason = FaultReason::comm_lost;
    r.last_position_counts = pos;
    r.time_unix_ns = 1'700'000'000'123'456'789LL;
    r.cycle = 1000;
    pos += 123457;
    EXPECT_TRUE(c.records.push_back(r));
  }
  return c;
}

std::vector<std::uint8_t> encode(const ErrorJointsContents& c) {
  std::vector<std::uint8_t> buf(kErrorJointsMaxFileSize);
  auto size = encode_error_joints(c, ByteSpan(buf.data(), buf.size()));
  EXPECT_TRUE(size.ok());
  buf.resize(size.ok() ? size.value() : 0);
  return buf;
}

ErrorJointsDecoded decode(const std::vector<std::uint8_t>& bytes) {
  return decode_error_joints(ConstByteSpan(bytes.data(), bytes.size()));
}

// Every decoded record is one of the originals (damage never invents or alters a joint's record).
void expect_subset(const ErrorJointsDecoded& d, const ErrorJointsContents& original) {
  for (const LostJointRecord& r : d.contents.records) {
    const LostJointRecord* o = original.find(r.joint);
    ASSERT_NE(o, nullptr) << "invented joint " << int(r.joint);
    EXPECT_TRUE(same(r, *o)) << "altered joint " << int(r.joint);
  }
}

void refresh_header_crc(std::vector<std::uint8_t>& bytes) {
  store_le32(bytes.data() + 28, crc32(ConstByteSpan(bytes.data(), 28)));
}

TEST(ErrorJointsFile, RoundTripKeepsEveryField) {
  const ErrorJointsContents original = elbow_cut();
  const auto bytes = encode(original);
  EXPECT_EQ(bytes.size(), kErrorJointsHeaderSize + 4 * kErrorJointsRecordSize);
  const ErrorJointsDecoded d = decode(bytes);
  ASSERT_TRUE(d.status.ok()) << d.status.error().what;
  EXPECT_EQ(d.records_rejected, 0u);
  EXPECT_FALSE(d.salvaged);
  EXPECT_EQ(d.contents.sequence, 7u);
  ASSERT_EQ(d.contents.records.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_TRUE(same(d.contents.records[i], original.records[i]));
  EXPECT_EQ(d.contents.joints(), joints_lost_by_link_failure_at(joint_index_by_name("l_elbow")));
}

TEST(ErrorJointsFile, LayoutIsTheDocumentedOne) {
  const auto bytes = encode(elbow_cut());
  EXPECT_EQ(std::memcmp(bytes.data(), "RMEJ", 4), 0);
  EXPECT_EQ(load_le16(&bytes[4]), 1);   // version
  EXPECT_EQ(load_le16(&bytes[6]), 32);  // header size
  EXPECT_EQ(load_le16(&bytes[8]), 48);  // record size
  EXPECT_EQ(load_le16(&bytes[10]), 4);  // count
  EXPECT_EQ(load_le32(&bytes[12]), robot_fingerprint());
  EXPECT_EQ(load_le64(&bytes[16]), 7u);
  const std::uint8_t* r = &bytes[32];
  EXPECT_EQ(r[0], joint_index_by_name("l_elbow"));
  EXPECT_EQ(r[1], static_cast<std::uint8_t>(FaultReason::comm_lost));
  EXPECT_EQ(load_le32s(r + 4), -300000);
  EXPECT_EQ(load_le64s(r + 8), 1'700'000'000'123'456'789LL);
  EXPECT_EQ(load_le64(r + 16), 1000u);
  EXPECT_STREQ(reinterpret_cast<const char*>(r + 24), "l_elbow");
  EXPECT_EQ(load_le32(r + 44), crc32(ConstByteSpan(r, 44)));
}

TEST(ErrorJointsFile, NoLostJointsIsAValidFile) {
  ErrorJointsContents none;
  none.sequence = 3;
  const ErrorJointsDecoded d = decode(encode(none));
  EXPECT_TRUE(d.status.ok());
  EXPECT_EQ(d.contents.records.size(), 0u);
  EXPECT_EQ(d.contents.sequence, 3u);
}

TEST(ErrorJointsFile, EmptyFileIsReportedAsEmpty) {
  const ErrorJointsDecoded d = decode({});
  ASSERT_FALSE(d.status.ok());
  EXPECT_EQ(d.status.error().code, Errc::truncated);
  EXPECT_STREQ(d.status.error().what, "file is empty");
  EXPECT_TRUE(d.contents.records.empty());
}

TEST(ErrorJointsFile, EveryTruncationIsReportedAndKeepsOnlyCompleteRecords) {
  const ErrorJointsContents original = elbow_cut();
  const auto full = encode(original);
  for (std::size_t len = 1; len < full.size(); ++len) {
    const std::vector<std::uint8_t> cut(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(len));
    const ErrorJointsDecoded d = decode(cut);
    ASSERT_FALSE(d.status.ok()) << len;
    EXPECT_EQ(d.status.error().code, Errc::truncated) << len;
    expect_subset(d, original);
    const std::size_t complete = len < kErrorJointsHeaderSize ? 0 : (len - kErrorJointsHeaderSize) / kErrorJointsRecordSize;
    EXPECT_EQ(d.contents.records.size(), complete) << len;
  }
}

TEST(ErrorJointsFile, WrongVersionIsRefusedWithBothVersions) {
  auto bytes = encode(elbow_cut());
  store_le16(&bytes[4], 2);
  refresh_header_crc(bytes);
  const ErrorJointsDecoded d = decode(bytes);
  ASSERT_FALSE(d.status.ok());
  EXPECT_EQ(d.status.error().code, Errc::version);
  EXPECT_EQ(d.status.error().detail0, 2u);
  EXPECT_EQ(d.status.error().detail1, 1u);
  EXPECT_TRUE(d.contents.records.empty());
}

TEST(ErrorJointsFile, OversizedImageIsRefusedWithoutParsing) {
  auto bytes = encode(elbow_cut());
  bytes.resize(kErrorJointsMaxFileSize + 1, 0);
  const ErrorJointsDecoded d = decode(bytes);
  ASSERT_FALSE(d.status.ok());
  EXPECT_EQ(d.status.error().code, Errc::capacity_exceeded);
  EXPECT_TRUE(d.contents.records.empty());
}

TEST(ErrorJointsFile, GarbageIsNotAnErrorJointsFile) {
  std::mt19937 rng(42);
  for (int round = 0; round < 200; ++round) {
    std::vector<std::uint8_t> bytes(1 + rng() % kErrorJointsMaxFileSize);
    for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
    const ErrorJointsDecoded d = decode(bytes);
    ASSERT_FALSE(d.status.ok());
    EXPECT_TRUE(d.contents.records.empty());
  }
  const ErrorJointsDecoded text = decode(std::vector<std::uint8_t>{'h', 'e', 'l', 'l', 'o', '\n'});
  EXPECT_STREQ(text.status.error().what, "not an error-joints file (bad magic)");
}

TEST(ErrorJointsFile, CorruptRecordIsDroppedAndTheOthersKept) {
  const ErrorJointsContents original = elbow_cut();
  auto bytes = encode(original);
  bytes[32 + 48 + 5] ^= 0x10;  // second record's position
  const ErrorJointsDecoded d = decode(bytes);
  ASSERT_FALSE(d.status.ok());
  EXPECT_EQ(d.status.error().code, Errc::checksum);
  EXPECT_EQ(d.status.error().detail0, 1u);  // record index
  EXPECT_EQ(d.records_rejected, 1u);
  EXPECT_EQ(d.contents.records.size(), 3u);
  expect_subset(d, original);
  EXPECT_EQ(d.contents.find(original.records[1].joint), nullptr);
}

TEST(ErrorJointsFile, CorruptHeaderStillYieldsRecordsThatProveThemselves) {
  const ErrorJointsContents original = elbow_cut();
  auto bytes = encode(original);
  bytes[10] = 200;  // record count, without fixing the header CRC
  const ErrorJointsDecoded d = decode(bytes);
  ASSERT_FALSE(d.status.ok());
  EXPECT_EQ(d.status.error().code, Errc::checksum);
  EXPECT_TRUE(d.salvaged);
  EXPECT_EQ(d.contents.records.size(), 4u);
  expect_subset(d, original);
}

TEST(ErrorJointsFile, FileOfAnotherRobotIsNotApplied) {
  auto bytes = encode(elbow_cut());
  store_le32(&bytes[12], robot_fingerprint() ^ 1u);
  refresh_header_crc(bytes);
  const ErrorJointsDecoded d = decode(bytes);
  ASSERT_FALSE(d.status.ok());
  EXPECT_EQ(d.status.error().code, Errc::mismatch);
  EXPECT_TRUE(d.contents.records.empty());
}

TEST(ErrorJointsFile, RecordCountAboveJointCountIsMalformed) {
  auto bytes = encode(elbow_cut());
  store_le16(&bytes[10], 22);
  refresh_header_crc(bytes);
  const ErrorJointsDecoded d = decode(bytes);
  EXPECT_EQ(d.status.error().code, Errc::malformed);
  EXPECT_EQ(d.contents.records.size(), 4u);  // still salvaged by their own checksums
}

TEST(ErrorJointsFile, DuplicateJointAndTrailingBytesAreReported) {
  const ErrorJointsContents original = elbow_cut();
  auto bytes = encode(original);
  std::memcpy(&bytes[32 + 48], &bytes[32], 48);  // record 1 := record 0 (valid CRC, same joint)
  ErrorJointsDecoded d = decode(bytes);
  EXPECT_EQ(d.status.error().code, Errc::malformed);
  EXPECT_STREQ(d.status.error().what, "record joint listed twice");
  EXPECT_EQ(d.contents.records.size(), 3u);

  bytes = encode(original);
  bytes.push_back(0);
  d = decode(bytes);
  EXPECT_STREQ(d.status.error().what, "bytes after the last record");
  EXPECT_EQ(d.contents.records.size(), 4u);
}

TEST(ErrorJointsFile, NoSingleBitFlipAltersOrInventsARecord) {
  const ErrorJointsContents original = elbow_cut();
  const auto good = encode(original);
  for (std::size_t bit = 0; bit < good.size() * 8; ++bit) {
    auto bytes = good;
    bytes[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    const ErrorJointsDecoded d = decode(bytes);
    EXPECT_FALSE(d.status.ok()) << "bit " << bit;
    expect_subset(d, original);
    if (bit >= kErrorJointsHeaderSize * 8) {
      EXPECT_EQ(d.contents.records.size(), 3u) << "bit " << bit;  // only the flipped record is lost
    }
  }
}

TEST(ErrorJointsFile, EncoderRefusesRecordsItCouldNotReadBack) {
  std::array<std::uint8_t, kErrorJointsMaxFileSize> buf{};
  ErrorJointsContents c;
  LostJointRecord r;
  r.joint = 21;
  ASSERT_TRUE(c.records.push_back(r));
  EXPECT_FALSE(encode_error_joints(c, ByteSpan(buf)).ok());
  c.records[0].joint = 3;
  c.records[0].reason = FaultReason::none;
  EXPECT_FALSE(encode_error_joints(c, ByteSpan(buf)).ok());
  c.records[0].reason = FaultReason::comm_lost;
  ASSERT_TRUE(c.records.push_back(c.records[0]));
  EXPECT_FALSE(encode_error_joints(c, ByteSpan(buf)).ok());
  c.records.pop_back();
  EXPECT_FALSE(encode_error_joints(c, ByteSpan(buf.data(), 40)).ok());  // buffer too small
  EXPECT_TRUE(encode_error_joints(c, ByteSpan(buf)).ok());
}

// The fuzzer's seeds were written by an independent encoder (Python's struct and zlib.crc32, following
// docs/joint-manager.md); they must decode cleanly, and the elbow-cut seed byte-equal ours.
TEST(ErrorJointsFile, FilesFromTheDocumentedLayoutDecode) {
  const std::string dir = std::string(RESCUE_SOURCE_DIR) + "/tests/fuzz/seeds-fuzz_error_joints_file/";
  for (const char* name : {"elbow-cut.bin", "no-joints.bin", "drive-fault-waist.bin"}) {
    std::ifstream in(dir + name, std::ios::binary);
    ASSERT_TRUE(in) << name;
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const ErrorJointsDecoded d = decode(bytes);
    EXPECT_TRUE(d.status.ok()) << name << ": " << d.status.error().what;
    if (std::string(name) == "elbow-cut.bin") {
      ErrorJointsContents c = elbow_cut();
      for (std::size_t i = 0; i < c.records.size(); ++i) {
        c.records[i].last_position_counts = -300000 + static_cast<std::int32_t>(c.records[i].joint) * 1000;
      }
      EXPECT_EQ(encode(c), bytes);
    }
  }
}

}  // namespace
}  // namespace rescue
