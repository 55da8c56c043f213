// hal/files/durable_file: atomic replacement, capped reads that refuse oversized and non-regular files, and
// directory creation.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <fstream>
#include <string>

#include "hal/files/durable_file.hpp"
#include "tests/support/temp_directory.hpp"

namespace rescue::hal {
namespace {

using DurableFile = testing::TempDirectoryTest;
using testing::bytes_of;

std::string read_all(const std::string& p) {
  std::array<std::uint8_t, 256> buf{};
  auto n = read_file_capped(p.c_str(), ByteSpan(buf));
  EXPECT_TRUE(n.ok()) << (n.ok() ? "" : n.error().what);
  return n.ok() ? std::string(reinterpret_cast<const char*>(buf.data()), n.value()) : std::string();
}

TEST_F(DurableFile, WriteCreatesThenReplacesAndLeavesNoTemporary) {
  ASSERT_TRUE(write_file_atomically(dir_.c_str(), "f.bin", bytes_of("first")).ok());
  EXPECT_EQ(read_all(path("f.bin")), "first");
  ASSERT_TRUE(write_file_atomically(dir_.c_str(), "f.bin", bytes_of("second, longer")).ok());
  EXPECT_EQ(read_all(path("f.bin")), "second, longer");
  EXPECT_NE(access(path("f.bin.tmp").c_str(), F_OK), 0);
}

TEST_F(DurableFile, StaleTemporaryFromACrashedWriterIsOverwritten) {
  std::ofstream(path("f.bin.tmp")) << "torn garbage from a killed writer, much longer than the new file";
  ASSERT_TRUE(write_file_atomically(dir_.c_str(), "f.bin", bytes_of("new")).ok());
  EXPECT_EQ(read_all(path("f.bin")), "new");
}

TEST_F(DurableFile, FailedWriteLeavesTheOldFile) {
  ASSERT_TRUE(write_file_atomically(dir_.c_str(), "f.bin", bytes_of("old")).ok());
  ASSERT_EQ(mkdir(path("f.bin.tmp").c_str(), 0700), 0);  // the temporary cannot be created
  const Status s = write_file_atomically(dir_.c_str(), "f.bin", bytes_of("new"));
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(read_all(path("f.bin")), "old");
}

TEST_F(DurableFile, MissingDirectoryOrFileIsNotFound) {
  EXPECT_EQ(write_file_atomically((dir_ + "/none").c_str(), "f", bytes_of("x")).error().code, Errc::not_found);
  std::array<std::uint8_t, 8> buf{};
  EXPECT_EQ(read_file_capped(path("absent").c_str(), ByteSpan(buf)).error().code, Errc::not_found);
}

TEST_F(DurableFile, ReadRefusesFilesLargerThanTheCap) {
  ASSERT_TRUE(write_file_atomically(dir_.c_str(), "big", bytes_of(std::string(100, 'x'))).ok());
  std::array<std::uint8_t, 99> small{};
  const auto r = read_file_capped(path("big").c_str(), ByteSpan(small));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::capacity_exceeded);
  EXPECT_EQ(r.error().detail0, 100u);
  std::array<std::uint8_t, 100> exact{};
  EXPECT_EQ(read_file_capped(path("big").c_str(), ByteSpan(exact)).value_or(0), 100u);
}

TEST_F(DurableFile, ReadRefusesFifosAndDirectoriesWithoutBlocking) {
  ASSERT_EQ(mkfifo(path("fifo").c_str(), 0600), 0);
  std::array<std::uint8_t, 8> buf{};
  EXPECT_EQ(read_file_capped(path("fifo").c_str(), ByteSpan(buf)).error().code, Errc::malformed);
  EXPECT_FALSE(read_file_capped(dir_.c_str(), ByteSpan(buf)).ok());
}

TEST_F(DurableFile, EmptyFileReadsAsZeroBytes) {
  std::ofstream(path("empty")).close();
  std::array<std::uint8_t, 8> buf{};
  EXPECT_EQ(read_file_capped(path("empty").c_str(), ByteSpan(buf)).value_or(99), 0u);
}

TEST_F(DurableFile, RenameDurablyMovesAFileAside) {
  ASSERT_TRUE(write_file_atomically(dir_.c_str(), "a", bytes_of("keep me")).ok());
  ASSERT_TRUE(rename_durably(dir_.c_str(), "a", "a.unusable").ok());
  EXPECT_EQ(read_all(path("a.unusable")), "keep me");
  EXPECT_FALSE(rename_durably(dir_.c_str(), "a", "b").ok());
}

TEST_F(DurableFile, MakeDirectoriesCreatesEveryLevelAndAcceptsExisting) {
  const std::string deep = dir_ + "/x/y/z";
  ASSERT_TRUE(make_directories(deep.c_str(), 0700).ok());
  struct stat st {};
  ASSERT_EQ(stat(deep.c_str(), &st), 0);
  EXPECT_TRUE(S_ISDIR(st.st_mode));
  EXPECT_EQ(st.st_mode & 0777, 0700u);
  EXPECT_TRUE(make_directories(deep.c_str(), 0700).ok());
  std::ofstream(path("file")).close();
  EXPECT_FALSE(make_directories(path("file").c_str(), 0700).ok());
  EXPECT_FALSE(make_directories("", 0700).ok());
}

TEST_F(DurableFile, OverlongPathsAreRefused) {
  const std::string name(kMaxPathLength, 'n');
  EXPECT_EQ(join_path(dir_.c_str(), name.c_str()).error().code, Errc::out_of_range);
  EXPECT_FALSE(write_file_atomically(dir_.c_str(), name.c_str(), bytes_of("x")).ok());
}

}  // namespace
}  // namespace rescue::hal
