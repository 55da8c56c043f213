// Issue 11 item 2: `rescue-motion run` after a link cut, with the error-joints file damaged the ways a
// safety engineer damaged it (one flipped byte in record 2, 3 or 4; truncation to 80, 128 or 223 bytes;
// a header count below the records present), starts, reaches OP, and does so again on the next start.
// The salvage follows the wiring (a joint behind a salvaged lost joint was unreachable too), the message
// says what was salvaged and what the operator can do, and each damaged original is kept under its own
// name. Before the fix: "bring-up failed at DC delays: slave present without its upstream slave" on
// every start, and "error-joints file not used" although records were used.
// Issue 35 item 12: a run leaves the file and its second copy; with the copy, a damaged file loses no
// record (the copy is used); without a readable copy, every joint the salvage does not list is held in
// Error too, on this start and the next, until cleared by name.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "core/base/crc32.hpp"
#include "core/base/endian.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
const char* const kCutJoints = "l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand";

test::CommandOutput run(const std::string& arguments) { return test::run_command(kBinary + " run " + arguments + " 2>&1"); }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void write_all(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// The file a link cut at l_elbow leaves (4 records, 224 bytes), made once.
const std::string& cut_file() {
  static const std::string bytes = [] {
    testing::TempStateDir dir;
    const test::CommandOutput cut = run("--scenario link-cut --state-dir " + dir.path);
    EXPECT_EQ(cut.exit_status, 0) << cut.out;
    return read_all(dir.file());
  }();
  return bytes;
}

struct Damage {
  const char* name;
  std::string (*apply)(const std::string&);
};

// Flips a bit inside record N's time field: only the record's CRC notices. The record number is a
// template argument and the bytes are copied through a vector so that GCC -O3, which inlines this into
// each lambda, does not mistake the moved-from string for a short in-object one (-Wstringop-overflow).
template <std::size_t kRecord>
std::string flip_in_record(const std::string& file) {
  std::vector<char> bytes(file.begin(), file.end());
  bytes.at(32 + (kRecord - 1) * 48 + 10) ^= 0x40;
  return std::string(bytes.begin(), bytes.end());
}
std::string header_count_two(const std::string& file) {
  std::string bytes = file;
  auto* h = reinterpret_cast<std::uint8_t*>(bytes.data());
  store_le16(h + 10, 2);
  store_le32(h + 28, crc32(ConstByteSpan(h, 28)));  // a consistent header that says 2 of the 4
  return bytes;
}

const Damage kDamages[] = {
    {"FlipRecord2", flip_in_record<2>},
    {"FlipRecord3", flip_in_record<3>},
    {"FlipRecord4", flip_in_record<4>},
    {"TruncateTo80", [](const std::string& b) { return b.substr(0, 80); }},
    {"TruncateTo128", [](const std::string& b) { return b.substr(0, 128); }},
    {"TruncateTo223", [](const std::string& b) { return b.substr(0, 223); }},
    {"HeaderCountBelowRecords", header_count_two},
};

class DamagedErrorFile : public ::testing::TestWithParam<Damage> {};

// Every joint in Error: the run ends "the robot ended in error", exit status 3 (docs/deploy.md).
constexpr int kRobotError = 3;

// Every joint's name, as the start-up lines list them.
std::string all_joint_names() {
  char names[kJointNamesCapacity];
  format_joint_names(kAllJoints, names, sizeof names);
  return names;
}

// What a link cut leaves: the file and its second copy; the damage is in the file.
TEST_P(DamagedErrorFile, TheSecondCopyKeepsEveryLossAndTheNextStartIsClean) {
  ASSERT_EQ(cut_file().size(), 224u);
  testing::TempStateDir dir;
  write_all(dir.file(), GetParam().apply(cut_file()));
  write_all(dir.path + "/" + ErrorJointsFileStorage::kCopyName, cut_file());

  const test::CommandOutput first = run("--duration 0.2 --state-dir " + dir.path);
  EXPECT_EQ(first.exit_status, 0) << first.out;
  EXPECT_TRUE(contains(first.out, "network in OP")) << first.out;
  EXPECT_FALSE(contains(first.out, "bring-up failed")) << first.out;
  EXPECT_TRUE(contains(first.out, "its second copy")) << first.out;
  EXPECT_TRUE(contains(first.out, std::string("restored lost joints ") + kCutJoints + " from")) << first.out;
  EXPECT_EQ(access((dir.file() + ".unusable").c_str(), F_OK), 0) << "the damaged original is kept";

  const test::CommandOutput second = run("--duration 0.2 --state-dir " + dir.path);
  EXPECT_EQ(second.exit_status, 0) << second.out;
  EXPECT_TRUE(contains(second.out, "network in OP")) << second.out;
  EXPECT_TRUE(contains(second.out, std::string("restored lost joints ") + kCutJoints + " from")) << second.out;
  EXPECT_FALSE(contains(second.out, "damaged")) << second.out;
  EXPECT_FALSE(contains(second.out, "second copy")) << second.out;
}

// No readable copy (a file from before the copy existed): the salvage follows the wiring, and every
// joint it does not list is held too, on the next start as well.
TEST_P(DamagedErrorFile, WithoutACopyTheSalvageFollowsTheWiringAndEveryOtherJointIsHeld) {
  testing::TempStateDir dir;
  write_all(dir.file(), GetParam().apply(cut_file()));

  const test::CommandOutput first = run("--duration 0.2 --state-dir " + dir.path);
  EXPECT_EQ(first.exit_status, kRobotError) << first.out;
  EXPECT_TRUE(contains(first.out, "network in OP")) << first.out;
  EXPECT_FALSE(contains(first.out, "bring-up failed")) << first.out;
  EXPECT_TRUE(contains(first.out, "error-joints file damaged")) << first.out;
  EXPECT_TRUE(contains(first.out, "salvaged")) << first.out;
  EXPECT_TRUE(contains(first.out, "no readable record of the lost joints")) << first.out;
  EXPECT_TRUE(contains(first.out, "restored lost joints " + all_joint_names() + " from")) << first.out;
  EXPECT_EQ(access((dir.file() + ".unusable").c_str(), F_OK), 0) << "the damaged original is kept";

  const test::CommandOutput second = run("--duration 0.2 --state-dir " + dir.path);
  EXPECT_EQ(second.exit_status, kRobotError) << second.out;
  EXPECT_TRUE(contains(second.out, "restored lost joints " + all_joint_names() + " from")) << second.out;
  EXPECT_FALSE(contains(second.out, "damaged")) << second.out;
}

INSTANTIATE_TEST_SUITE_P(Issue11, DamagedErrorFile, ::testing::ValuesIn(kDamages),
                         [](const ::testing::TestParamInfo<Damage>& p) { return std::string(p.param.name); });

TEST(DamagedErrorFileSetAside, EachDamagedOriginalKeepsItsOwnName) {
  testing::TempStateDir dir;
  write_all(dir.file(), flip_in_record<2>(cut_file()));  // no copy: every other joint held, exit 3
  ASSERT_EQ(run("--duration 0.1 --state-dir " + dir.path).exit_status, kRobotError);
  write_all(dir.file(), cut_file().substr(0, 80));  // the copy that run wrote stands in
  const test::CommandOutput out = run("--duration 0.1 --state-dir " + dir.path);
  ASSERT_EQ(out.exit_status, kRobotError) << out.out;
  EXPECT_EQ(read_all(dir.file() + ".unusable"), flip_in_record<2>(cut_file())) << "the first set-aside is not overwritten";
  EXPECT_EQ(read_all(dir.file() + ".unusable.1"), cut_file().substr(0, 80));
  EXPECT_TRUE(contains(out.out, "error-joints.bin.unusable.1")) << out.out;
}

TEST(DamagedErrorFileSetAside, ACompleteNewerTemporaryFileIsReportedAndItsJointsKept) {
  // A kill between the temporary file's fsync and the rename: the .tmp holds a newer, complete file.
  testing::TempStateDir older;
  std::string old_file = cut_file();
  {
    auto* h = reinterpret_cast<std::uint8_t*>(old_file.data());
    store_le16(h + 10, 1);  // an older file: l_elbow only, sequence lower
    store_le64(h + 16, load_le64(h + 16) - 1);
    store_le32(h + 28, crc32(ConstByteSpan(h, 28)));
    old_file.resize(80);
  }
  write_all(older.file(), old_file);
  write_all(older.file() + ".tmp", cut_file());
  const test::CommandOutput out = run("--duration 0.1 --state-dir " + older.path);
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "error-joints.bin.tmp")) << out.out;
  EXPECT_TRUE(contains(out.out, "interrupted")) << out.out;
  EXPECT_TRUE(contains(out.out, std::string("restored lost joints ") + kCutJoints)) << out.out;
}

TEST(DamagedErrorFileSetAside, ADanglingSymlinkIsReportedNotTakenForNoFile) {
  testing::TempStateDir dir;
  ASSERT_EQ(symlink((dir.path + "/gone").c_str(), dir.file().c_str()), 0);
  const test::CommandOutput out = run("--duration 0.1 --state-dir " + dir.path);
  EXPECT_EQ(out.exit_status, kRobotError) << "no readable record: every joint held\n" << out.out;
  EXPECT_TRUE(contains(out.out, "symbolic link")) << out.out;
  EXPECT_FALSE(contains(out.out, "error-joints file: none")) << out.out;
}

}  // namespace
}  // namespace rescue::app
