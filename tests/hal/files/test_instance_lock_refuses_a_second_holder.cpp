// Issue 11 item 3: one instance per state directory and per raw NIC. A second taker is refused with
// `busy` and the holder's pid (here the holder is this process: flock locks belong to the open file,
// abstract socket names to the bound socket, so a second take from the same process conflicts too).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

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

}  // namespace
}  // namespace rescue::hal
