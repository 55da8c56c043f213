// Start-up with whatever is in the state directory: no file, a good one, or an empty, truncated,
// garbage, wrong-version, oversized, corrupt, foreign or non-regular one, and no second copy (the copy
// is test_error_joints_loss_survives_a_damaged_file's). Every case gives a clear reason, never crashes
// or hangs, restores every record that can be trusted and keeps a damaged file aside for post-mortem;
// a damaged file with no readable copy holds every other joint in Error too (which were lost cannot be
// known), until the operator clears each by name: a safe start that forgets no loss.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <functional>
#include <vector>

#include "drivers/joint/joint_units.hpp"
#include "core/base/endian.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

using fsm::JointState;
using testing::Rig;

const JointMask kElbowCut = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));

std::vector<std::uint8_t> good_file() {
  ErrorJointsContents c;
  c.sequence = 5;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((kElbowCut & joint_bit(j)) == 0) continue;
    (void)c.records.push_back(LostJointRecord{static_cast<std::uint8_t>(j), FaultReason::comm_lost,
                                              static_cast<std::int32_t>(1000 * j), 1, 2});
  }
  std::vector<std::uint8_t> bytes(kErrorJointsMaxFileSize);
  bytes.resize(encode_error_joints(c, ByteSpan(bytes.data(), bytes.size())).value_or(0));
  return bytes;
}

struct Case {
  const char* name;
  std::function<void(const std::string& path)> make;  // puts something at the file's path (or nothing)
  bool present;
  Errc code;             // Errc::ok: the file is fine
  const char* reason;    // what the log line says
  int restored;          // joints in Error after the start (all 21: no readable record)
};

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                              static_cast<std::streamsize>(bytes.size()));
}

const Case kCases[] = {
    {"absent", [](const std::string&) {}, false, Errc::not_found, "error-joints file: none", 0},
    {"good", [](const std::string& p) { write_bytes(p, good_file()); }, true, Errc::ok, "restored l_elbow", 4},
    {"empty", [](const std::string& p) { write_bytes(p, {}); }, true, Errc::truncated, "file is empty", 21},
    {"truncated_mid_record",
     [](const std::string& p) {
       auto b = good_file();
       b.resize(32 + 2 * 48 + 20);
       write_bytes(p, b);
     },
     true, Errc::truncated, "file shorter than its record count", 21},  // 2 salvaged, 2 behind them (wiring), the rest held
    {"truncated_header", [](const std::string& p) { write_bytes(p, {'R', 'M', 'E', 'J', 1}); }, true, Errc::truncated,
     "file shorter than its header", 21},
    {"garbage", [](const std::string& p) { write_bytes(p, std::vector<std::uint8_t>(300, 0xA5)); }, true,
     Errc::malformed, "not an error-joints file (bad magic)", 21},
    {"wrong_version",
     [](const std::string& p) {
       auto b = good_file();
       store_le16(&b[4], 9);
       write_bytes(p, b);
     },
     true, Errc::version, "unsupported error-joints file version", 21},
    {"oversized_beyond_read_cap",
     [](const std::string& p) { write_bytes(p, std::vector<std::uint8_t>(1 << 20, 'x')); }, true,
     Errc::capacity_exceeded, "file larger than the read cap", 21},
    {"oversized_within_read_cap",
     [](const std::string& p) {
       auto b = good_file();
       b.resize(2000, 0);
       write_bytes(p, b);
     },
     true, Errc::capacity_exceeded, "file larger than 21 records", 21},
    {"corrupt_record",
     [](const std::string& p) {
       auto b = good_file();
       b[32 + 48 * 3 + 9] ^= 0xFF;
       write_bytes(p, b);
     },
     true, Errc::checksum, "record checksum mismatch", 21},  // 3 salvaged, l_hand behind them (wiring), the rest held
    {"corrupt_header",
     [](const std::string& p) {
       auto b = good_file();
       b[17] ^= 0x01;  // sequence number
       write_bytes(p, b);
     },
     true, Errc::checksum, "header checksum mismatch", 21},
    {"fifo", [](const std::string& p) { ASSERT_EQ(mkfifo(p.c_str(), 0600), 0); }, true, Errc::malformed,
     "not a regular file", 21},
    {"directory", [](const std::string& p) { ASSERT_EQ(mkdir(p.c_str(), 0700), 0); }, true, Errc::malformed,
     "not a regular file", 21},
};

class DamagedErrorFile : public ::testing::TestWithParam<Case> {};

TEST_P(DamagedErrorFile, StartsSafelyAndSaysWhy) {
  const Case& c = GetParam();
  testing::TempStateDir dir;
  c.make(dir.file());
  ErrorJointsFileStorage storage(dir.path.c_str());
  Rig rig(storage);
  JointManager manager(rig.ports());
  const RestoreReport report = manager.restore(0);

  EXPECT_EQ(report.file_present, c.present);
  if (c.code == Errc::ok || c.code == Errc::not_found) {
    EXPECT_TRUE(report.file_status.ok());
  } else {
    ASSERT_FALSE(report.file_status.ok());
    EXPECT_EQ(report.file_status.error().code, c.code) << report.file_status.error().what;
  }
  EXPECT_TRUE(rig.log.contains(c.reason)) << "log:\n" << (rig.log.lines.empty() ? "" : rig.log.lines[0]);

  // Restored joints in Error with their held position; every other joint Idle.
  EXPECT_EQ(__builtin_popcount(report.restored), c.restored);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const bool restored = (report.restored & joint_bit(j)) != 0;
    EXPECT_EQ(manager.statuses()[j].state, restored ? JointState::error : JointState::idle) << kJoints[j].name;
    if (restored && ((report.added_behind | report.held_unreadable) & joint_bit(j)) == 0) {  // else held position unknown
      EXPECT_EQ(manager.statuses()[j].held_position_rad, drivers::counts_to_rad(static_cast<std::int32_t>(1000 * j)));
    }
  }
  // Beyond the file's own records (salvaged, and the wiring behind them), only a damaged file holds
  // joints, and then every one it does not list.
  const bool damaged = c.code != Errc::ok && c.code != Errc::not_found;
  EXPECT_EQ(report.restored & ~(kElbowCut | report.held_unreadable), 0u);
  EXPECT_EQ(report.held_unreadable, damaged ? kAllJoints & ~(report.salvaged | report.added_behind) : 0u);
  if (damaged) {
    EXPECT_TRUE(rig.log.contains("no readable record of the lost joints"));
  }

  // A damaged regular file is kept aside, and what was trusted is durable again under the file's name.
  if (damaged && std::string(c.name) != "directory") {
    EXPECT_TRUE(report.set_aside);
    EXPECT_EQ(access((dir.path + "/" + ErrorJointsFileStorage::kSetAsideName).c_str(), F_OK), 0);
  }
  if (damaged && std::string(c.name) != "directory") {  // a directory at the name cannot be replaced
    const ErrorJointsLoad again = storage.load();
    EXPECT_TRUE(again.decoded.status.ok());
    EXPECT_EQ(again.decoded.contents.joints(), report.restored);
  }
  manager.step(hal::kNsPerMs);  // and it runs on
}

INSTANTIATE_TEST_SUITE_P(EveryKindOfFile, DamagedErrorFile, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace rescue::app
