// hal::create_file_durably: creates a file with its contents and mode through a temporary name, never
// replaces one already there (busy, the old contents untouched), takes the place of a temporary a
// killed writer left, leaves no temporary behind, and on a failure leaves no file at the name; and
// split_path, which gives it a path's directory and name.
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

using DurableCreate = testing::TempDirectoryTest;
using testing::bytes_of;

std::string read_all(const std::string& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST_F(DurableCreate, CreatesWithItsModeAndLeavesNoTemporary) {
  const mode_t old_umask = ::umask(0077);
  const Status made = create_file_durably(dir_.c_str(), "key", bytes_of("secret\n"), 0640);
  (void)::umask(old_umask);
  ASSERT_TRUE(made.ok()) << made.error().what;
  EXPECT_EQ(read_all(path("key")), "secret\n");
  struct stat st {};
  ASSERT_EQ(::stat(path("key").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640U) << "the mode asked for, whatever the umask";
  EXPECT_NE(::access(path("key.new").c_str(), F_OK), 0);
}

TEST_F(DurableCreate, NeverReplacesAFileAlreadyThere) {
  std::ofstream(path("key")) << "the robot's key";
  const Status made = create_file_durably(dir_.c_str(), "key", bytes_of("another\n"), 0600);
  ASSERT_FALSE(made.ok());
  EXPECT_EQ(made.error().code, Errc::busy);
  EXPECT_EQ(read_all(path("key")), "the robot's key");
  EXPECT_NE(::access(path("key.new").c_str(), F_OK), 0) << "nothing written";
}

TEST_F(DurableCreate, TakesThePlaceOfATemporaryAKilledWriterLeft) {
  std::ofstream(path("key.new")) << "half a key from a keygen stopped by its deadline";
  ASSERT_TRUE(create_file_durably(dir_.c_str(), "key", bytes_of("whole\n"), 0600).ok());
  EXPECT_EQ(read_all(path("key")), "whole\n");
  EXPECT_NE(::access(path("key.new").c_str(), F_OK), 0);
}

TEST_F(DurableCreate, AFailedCreateLeavesNoFileAtTheName) {
  ASSERT_EQ(::mkdir(path("key.new").c_str(), 0700), 0);  // a directory at the temporary name: unlink fails
  const Status made = create_file_durably(dir_.c_str(), "key", bytes_of("whole\n"), 0600);
  EXPECT_FALSE(made.ok());
  EXPECT_NE(::access(path("key").c_str(), F_OK), 0);
}

TEST(SplitPath, GivesTheDirectoryAndTheNameOfEveryKindOfPath) {
  const struct {
    const char* path;
    const char* dir;
    const char* name;
  } cases[] = {{"/var/lib/rescue-motion/operator.key", "/var/lib/rescue-motion", "operator.key"},
               {"/operator.key", "/", "operator.key"},
               {"operator.key", ".", "operator.key"},
               {"state/operator.key", "state", "operator.key"}};
  for (const auto& c : cases) {
    const Result<DirAndName> split = split_path(c.path);
    ASSERT_TRUE(split.ok()) << c.path;
    EXPECT_STREQ(split.value().dir.c_str(), c.dir) << c.path;
    EXPECT_STREQ(split.value().name, c.name) << c.path;
  }
  for (const char* bad : {"", "state/", "/"}) {
    const Result<DirAndName> split = split_path(bad);
    ASSERT_FALSE(split.ok()) << bad;
    EXPECT_EQ(split.error().code, Errc::invalid_argument) << bad;
  }
}

}  // namespace
}  // namespace rescue::hal
