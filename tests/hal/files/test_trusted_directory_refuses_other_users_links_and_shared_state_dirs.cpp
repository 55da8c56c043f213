// hal/files/trusted_file.hpp, open_trusted_directory and create_regular_in: an output file is never
// written through a directory link another user made (with fs.protected_symlinks=0 such a link in a
// shared sticky directory led root's `--timing-out` and `--capture` into root's own 0700 directory),
// never into a directory another user owns or may write (bench fig4 --out), never over a hard link;
// and a shared sticky directory (mode 1777, like /tmp) is refused as the state directory itself
// (anyone could hold its lock or plant its error-joints file), though accepted on the way to one.
// The other-user cases chown to `nobody` and so need root; without it they are skipped, saying why.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "hal/files/trusted_file.hpp"
#include "tests/support/temp_directory.hpp"

namespace rescue::hal {
namespace {

constexpr uid_t kNobody = 65534;

using TrustedDirectory = testing::TempDirectoryTest;

void write(const std::string& path, const char* text) {
  std::ofstream(path) << text;
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool says(const FileProblem& why, const char* text) { return std::string(why.c_str()).find(text) != std::string::npos; }

// A root-owned sticky directory everyone may write, as /tmp is: made inside a private one.
std::string make_shared_sticky(const std::string& dir) {
  const std::string shared = dir + "/shared";
  EXPECT_EQ(::mkdir(shared.c_str(), 0700), 0);
  EXPECT_EQ(::chmod(shared.c_str(), 01777), 0);
  return shared;
}

TEST_F(TrustedDirectory, AnotherUsersDirectoryLinkIsNotFollowedIntoOurOwnFiles) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to make a link owned by nobody (uid 65534)";
  const std::string shared = make_shared_sticky(dir_);
  const std::string mine = path("private");
  ASSERT_EQ(::mkdir(mine.c_str(), 0700), 0);
  write(mine + "/timing.csv", "root's data");
  // nobody's link in the shared directory, to our 0700 directory.
  const std::string link = shared + "/x";
  ASSERT_EQ(::symlink(mine.c_str(), link.c_str()), 0);
  ASSERT_EQ(::lchown(link.c_str(), kNobody, kNobody), 0);
  FileProblem why;
  const Result<OpenFile> out = open_regular_for_write((link + "/timing.csv").c_str(), 0644, why);
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.error().code, Errc::permission_denied);
  EXPECT_TRUE(says(why, (link + " is a symbolic link owned by uid 65534").c_str())) << why.c_str();
  EXPECT_FALSE(open_trusted_directory(link.c_str(), DirectoryUse::output, why).ok());
  EXPECT_EQ(read(mine + "/timing.csv"), "root's data");
  // The same link made by this user is followed.
  const std::string own_link = shared + "/y";
  ASSERT_EQ(::symlink(mine.c_str(), own_link.c_str()), 0);
  EXPECT_TRUE(open_regular_for_write((own_link + "/timing.csv").c_str(), 0644, why).ok()) << why.c_str();
  EXPECT_EQ(read(mine + "/timing.csv"), "");
}

TEST_F(TrustedDirectory, ALinkFurtherDownTheTargetOfALinkIsCheckedToo) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to make a link owned by nobody (uid 65534)";
  const std::string shared = make_shared_sticky(dir_);
  const std::string mine = path("private");
  ASSERT_EQ(::mkdir(mine.c_str(), 0700), 0);
  const std::string inner = shared + "/inner";  // nobody's
  ASSERT_EQ(::symlink(mine.c_str(), inner.c_str()), 0);
  ASSERT_EQ(::lchown(inner.c_str(), kNobody, kNobody), 0);
  const std::string outer = path("outer");  // ours, to nobody's
  ASSERT_EQ(::symlink(inner.c_str(), outer.c_str()), 0);
  FileProblem why;
  EXPECT_FALSE(open_regular_for_write((outer + "/f").c_str(), 0644, why).ok());
  EXPECT_TRUE(says(why, "owned by uid 65534")) << why.c_str();
}

TEST_F(TrustedDirectory, AnOutputDirectoryOfAnotherUserOrWritableByOthersIsRefused) {
  const std::string out = path("out");
  ASSERT_EQ(::mkdir(out.c_str(), 0700), 0);
  ASSERT_EQ(::chmod(out.c_str(), 0777), 0);
  FileProblem why;
  EXPECT_FALSE(open_trusted_directory(out.c_str(), DirectoryUse::output, why).ok());
  EXPECT_TRUE(says(why, "writable by group or others")) << why.c_str();
  ASSERT_EQ(::chmod(out.c_str(), 0755), 0);
  EXPECT_TRUE(open_trusted_directory(out.c_str(), DirectoryUse::output, why).ok()) << why.c_str();
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to chown a directory to nobody (uid 65534)";
  ASSERT_EQ(::chown(out.c_str(), kNobody, kNobody), 0);
  EXPECT_FALSE(open_trusted_directory(out.c_str(), DirectoryUse::output, why).ok());
  EXPECT_TRUE(says(why, "owned by uid 65534")) << why.c_str();
}

TEST_F(TrustedDirectory, AHardLinkIsNeverTruncated) {
  const std::string keep = path("keep");
  write(keep, "data");
  const std::string other = path("other-name");
  ASSERT_EQ(::link(keep.c_str(), other.c_str()), 0);
  FileProblem why;
  EXPECT_FALSE(open_regular_for_write(other.c_str(), 0644, why).ok());
  EXPECT_TRUE(says(why, "hard link")) << why.c_str();
  EXPECT_EQ(read(keep), "data");
}

TEST_F(TrustedDirectory, ASharedStickyDirectoryIsRefusedAsTheStateDirectoryButPassesOnTheWay) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root: a shared sticky directory passes only when root owns it";
  const std::string shared = make_shared_sticky(dir_);
  FileProblem why;
  const Status state = check_trusted_directory(shared.c_str(), why);
  ASSERT_FALSE(state.ok());
  EXPECT_EQ(state.error().code, Errc::permission_denied);
  EXPECT_TRUE(says(why, ("state directory " + shared + " is shared").c_str())) << why.c_str();
  // As an output directory it passes (our entries there are ours alone), and a directory of ours
  // inside it passes as a state directory.
  EXPECT_TRUE(open_trusted_directory(shared.c_str(), DirectoryUse::output, why).ok()) << why.c_str();
  const std::string own = shared + "/state";
  ASSERT_EQ(::mkdir(own.c_str(), 0700), 0);
  EXPECT_TRUE(check_trusted_directory(own.c_str(), why).ok()) << why.c_str();
  // Reached through "." and a relative path too.
  ASSERT_EQ(::chdir(shared.c_str()), 0);
  EXPECT_FALSE(check_trusted_directory(".", why).ok());
  EXPECT_TRUE(check_trusted_directory("state", why).ok()) << why.c_str();
  ASSERT_EQ(::chdir("/"), 0);
}

}  // namespace
}  // namespace rescue::hal
