// hal/files/trusted_file.hpp: a FIFO, a directory or a device at a file's name is refused at once
// (never a hang in open()), and the StrictModes check refuses a file or a directory above it that
// another user owns or that group or others may write, and a symbolic link to such a target.
// The other-user cases chown to `nobody` and so need root; without it they are skipped, saying why.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <cstdlib>
#include <string>

#include "hal/files/trusted_file.hpp"

namespace rescue::hal {
namespace {

constexpr uid_t kNobody = 65534;

struct TempDir {
  TempDir() {
    char templ[] = "/tmp/rm-trusted-XXXXXX";
    path = ::mkdtemp(templ);
  }
  ~TempDir() { (void)std::system(("rm -rf " + path).c_str()); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const char* name) const { return path + "/" + name; }
  std::string path;
};

void write(const std::string& path, const char* text, mode_t mode) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, mode);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::write(fd, text, std::strlen(text)), static_cast<ssize_t>(std::strlen(text)));
  ASSERT_EQ(::fchmod(fd, mode), 0);
  (void)::close(fd);
}

bool says(const FileProblem& why, const char* text) { return std::string(why.c_str()).find(text) != std::string::npos; }

template <typename F>
double seconds_of(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(TrustedFile, AFifoADirectoryAndADeviceAreRefusedAtOnceForReadingAndWriting) {
  TempDir dir;
  const std::string fifo = dir.file("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string sub = dir.file("sub");
  ASSERT_EQ(::mkdir(sub.c_str(), 0700), 0);
  struct Case {
    std::string path;
    const char* kind;
  };
  for (const Case& c : {Case{fifo, "FIFO"}, Case{sub, "directory"}, Case{"/dev/zero", "character device"}}) {
    FileProblem why;
    const double took = seconds_of([&] {
      const Result<OpenFile> r = open_regular_for_read(c.path.c_str(), why);
      EXPECT_FALSE(r.ok()) << c.path;
    });
    EXPECT_LT(took, 2.0) << c.path;
    EXPECT_TRUE(says(why, c.kind)) << why.c_str();
    EXPECT_TRUE(says(why, c.path.c_str())) << why.c_str();
    FileProblem trusted_why;
    EXPECT_FALSE(open_trusted_for_read(c.path.c_str(), Secrecy::secret, trusted_why).ok()) << c.path;
    EXPECT_TRUE(says(trusted_why, c.kind)) << trusted_why.c_str();
    if (c.path != "/dev/zero") {  // writing to a device would need the device to be ours
      FileProblem write_why;
      EXPECT_FALSE(open_regular_for_write(c.path.c_str(), 0644, write_why).ok()) << c.path;
      EXPECT_TRUE(says(write_why, "not a regular file")) << write_why.c_str();
    }
  }
}

TEST(TrustedFile, AnOutputIsNeverWrittenThroughASymbolicLink) {
  TempDir dir;
  const std::string target = dir.file("target");
  write(target, "keep", 0644);
  const std::string link = dir.file("link");
  ASSERT_EQ(::symlink(target.c_str(), link.c_str()), 0);
  FileProblem why;
  EXPECT_FALSE(open_regular_for_write(link.c_str(), 0644, why).ok());
  EXPECT_TRUE(says(why, "symbolic link")) << why.c_str();
  struct stat st {};
  ASSERT_EQ(::stat(target.c_str(), &st), 0);
  EXPECT_EQ(st.st_size, 4) << "the link's target was truncated";
  FileProblem ok_why;
  EXPECT_TRUE(open_regular_for_write(dir.file("new").c_str(), 0644, ok_why).ok()) << ok_why.c_str();
}

TEST(TrustedFile, AWritableFileOrDirectoryIsRefusedNamingThePathAndTheFix) {
  TempDir dir;
  const std::string key = dir.file("key");
  write(key, "x", 0600);
  FileProblem why;
  EXPECT_TRUE(open_trusted_for_read(key.c_str(), Secrecy::secret, why).ok()) << why.c_str();
  ASSERT_EQ(::chmod(key.c_str(), 0640), 0);
  EXPECT_FALSE(open_trusted_for_read(key.c_str(), Secrecy::secret, why).ok());
  EXPECT_TRUE(says(why, "readable by group or others")) << why.c_str();
  EXPECT_TRUE(open_trusted_for_read(key.c_str(), Secrecy::public_file, why).ok()) << why.c_str();
  ASSERT_EQ(::chmod(key.c_str(), 0666), 0);
  const Result<OpenFile> loose = open_trusted_for_read(key.c_str(), Secrecy::public_file, why);
  ASSERT_FALSE(loose.ok());
  EXPECT_EQ(loose.error().code, Errc::permission_denied);
  EXPECT_TRUE(says(why, ("chmod go-w " + key).c_str())) << why.c_str();
  ASSERT_EQ(::chmod(key.c_str(), 0600), 0);
  ASSERT_EQ(::chmod(dir.path.c_str(), 0777), 0);
  EXPECT_FALSE(open_trusted_for_read(key.c_str(), Secrecy::secret, why).ok());
  EXPECT_TRUE(says(why, ("directory " + dir.path + " is writable by group or others").c_str())) << why.c_str();
  EXPECT_FALSE(check_trusted_directory(dir.path.c_str(), why).ok());
  ASSERT_EQ(::chmod(dir.path.c_str(), 0700), 0);
  EXPECT_TRUE(check_trusted_directory(dir.path.c_str(), why).ok()) << why.c_str();
  // /tmp is writable by everyone but root's and sticky: on the way to a state directory it passes
  // (nobody else can replace our entries); as the state directory itself it does not (anyone may
  // create an entry there first: tests/hal/files/test_trusted_directory_refuses_other_users_links_and_shared_state_dirs.cpp).
  EXPECT_TRUE(check_trusted_directory(dir.path.c_str(), why).ok()) << why.c_str();
  ASSERT_EQ(dir.path.rfind("/tmp/", 0), 0U);
}

TEST(TrustedFile, AFileOrDirectoryOfAnotherUserIsRefusedAndALinkIsFollowedOnlyToATrustedTarget) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to chown a file to nobody (uid 65534)";
  TempDir dir;
  const std::string key = dir.file("key");
  write(key, "x", 0600);
  ASSERT_EQ(::chown(key.c_str(), kNobody, kNobody), 0);
  FileProblem why;
  const Result<OpenFile> foreign = open_trusted_for_read(key.c_str(), Secrecy::secret, why);
  ASSERT_FALSE(foreign.ok());
  EXPECT_EQ(foreign.error().code, Errc::permission_denied);
  EXPECT_TRUE(says(why, "owned by uid 65534")) << why.c_str();
  EXPECT_TRUE(says(why, key.c_str())) << why.c_str();

  // A link of ours to a file of nobody's: refused, naming the link and its target.
  const std::string link = dir.file("link");
  ASSERT_EQ(::symlink(key.c_str(), link.c_str()), 0);
  EXPECT_FALSE(open_trusted_for_read(link.c_str(), Secrecy::secret, why).ok());
  EXPECT_TRUE(says(why, link.c_str()) && says(why, "owned by uid 65534")) << why.c_str();
  // A link to a trusted file is followed.
  const std::string mine = dir.file("mine");
  write(mine, "y", 0600);
  const std::string good_link = dir.file("good-link");
  ASSERT_EQ(::symlink(mine.c_str(), good_link.c_str()), 0);
  EXPECT_TRUE(open_trusted_for_read(good_link.c_str(), Secrecy::secret, why).ok()) << why.c_str();

  // A directory of nobody's above a file of ours.
  const std::string sub = dir.file("sub");
  ASSERT_EQ(::mkdir(sub.c_str(), 0755), 0);
  const std::string inner = sub + "/key";
  write(inner, "z", 0600);
  ASSERT_EQ(::chown(sub.c_str(), kNobody, kNobody), 0);
  EXPECT_FALSE(open_trusted_for_read(inner.c_str(), Secrecy::secret, why).ok());
  EXPECT_TRUE(says(why, ("directory " + sub + " is owned by uid 65534").c_str())) << why.c_str();
  EXPECT_FALSE(check_trusted_directory(sub.c_str(), why).ok());
}

}  // namespace
}  // namespace rescue::hal
