// Issue 11 item 3: one instance per state directory and per raw NIC. A second taker is refused with
// `busy` and the holder's pid (here the holder is this process: flock locks belong to the open file,
// abstract socket names to the bound socket, so a second take from the same process conflicts too).
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>

#include <cstdlib>
#include <string>

#include "hal/files/instance_lock.hpp"
#include "hal/files/state_dir.hpp"

namespace rescue::hal {
namespace {

std::string temp_dir() {
  std::string templ = ::testing::TempDir() + "lock-XXXXXX";
  return mkdtemp(templ.data()) != nullptr ? templ : std::string();
}

TEST(InstanceLock, SecondLockOfAStateDirectoryIsBusyAndNamesTheHolder) {
  const std::string dir = temp_dir();
  ASSERT_TRUE(lock_state_directory(dir.c_str()).ok());
  const Status second = lock_state_directory(dir.c_str());
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.error().code, Errc::busy);
  EXPECT_EQ(second.error().detail0, static_cast<std::uint32_t>(getpid()));
  (void)std::system(("rm -rf '" + dir + "'").c_str());
}

TEST(InstanceLock, SecondLockOfARawInterfaceIsBusyAndNamesTheHolder) {
  const std::string iface = "lk" + std::to_string(getpid() % 100000);
  ASSERT_TRUE(lock_raw_interface(iface.c_str()).ok());
  const Status second = lock_raw_interface(iface.c_str());
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.error().code, Errc::busy);
  EXPECT_EQ(second.error().detail0, static_cast<std::uint32_t>(getpid()));
  EXPECT_TRUE(lock_raw_interface((iface + "b").c_str()).ok()) << "another interface is another lock";
}

TEST(InstanceLock, AReadOnlyStateDirectoryIsSeenAtStart) {
  if (geteuid() == 0) GTEST_SKIP() << "root writes through permissions";
  const std::string dir = temp_dir();
  ASSERT_EQ(chmod(dir.c_str(), 0500), 0);
  const Status writable = check_writable(dir.c_str());
  EXPECT_FALSE(writable.ok());
  EXPECT_EQ(writable.error().code, Errc::permission_denied);
  (void)chmod(dir.c_str(), 0700);
  EXPECT_TRUE(check_writable(dir.c_str()).ok());
  (void)std::system(("rm -rf '" + dir + "'").c_str());
}

// Root writes through permissions (the test above skips), but not onto a read-only filesystem: the
// state directory on a read-only mount (private mount namespace, in a child) is seen at start too.
TEST(InstanceLock, AStateDirectoryOnAReadOnlyMountIsSeenEvenByRoot) {
  const std::string dir = temp_dir();
  ASSERT_FALSE(dir.empty());
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (unshare(CLONE_NEWNS) != 0 || mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
        mount("none", dir.c_str(), "tmpfs", MS_RDONLY, nullptr) != 0) {
      _exit(77);  // no mount namespace here (not privileged)
    }
    const Status writable = check_writable(dir.c_str());
    _exit(!writable.ok() && writable.error().code == Errc::permission_denied && writable.error().detail0 == EROFS ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  (void)rmdir(dir.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  if (WEXITSTATUS(status) == 77) GTEST_SKIP() << "cannot make a mount namespace (needs CAP_SYS_ADMIN)";
  EXPECT_EQ(WEXITSTATUS(status), 0) << "a read-only state directory was taken for writable";
}

}  // namespace
}  // namespace rescue::hal
