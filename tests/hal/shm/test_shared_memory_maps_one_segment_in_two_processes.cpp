// hal/shm/shared_memory.hpp: one name, one memory across processes; exclusive creation; errors as
// values for a bad name, a missing name, a name taken.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

#include "hal/shm/shared_memory.hpp"

namespace rescue::hal {
namespace {

TEST(SharedMemory, ChildWritesParentReads) {
  char name[64];
  (void)std::snprintf(name, sizeof name, "/rescue-hal-test-%d", static_cast<int>(::getpid()));
  (void)SharedMemory::unlink(name);
  Result<SharedMemory> created = SharedMemory::create_exclusive(name, 4096);
  ASSERT_TRUE(created.ok());
  EXPECT_EQ(created.value().size(), 4096U);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    Result<SharedMemory> opened = SharedMemory::open_existing(name);
    if (!opened.ok() || opened.value().size() != 4096) ::_exit(2);
    std::memcpy(opened.value().data(), "hello", 6);
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_STREQ(static_cast<const char*>(created.value().data()), "hello");
  EXPECT_EQ(SharedMemory::create_exclusive(name, 4096).error().code, Errc::busy);
  EXPECT_TRUE(SharedMemory::unlink(name).ok());
  EXPECT_EQ(SharedMemory::open_existing(name).error().code, Errc::not_found);
  EXPECT_EQ(SharedMemory::unlink(name).error().code, Errc::not_found);
  EXPECT_STREQ(static_cast<const char*>(created.value().data()), "hello");  // the mapping outlives the name
}

TEST(SharedMemory, BadNamesAreRefused) {
  EXPECT_EQ(SharedMemory::create_exclusive("x", 16).error().code, Errc::invalid_argument);
  EXPECT_EQ(SharedMemory::create_exclusive("/a/b", 16).error().code, Errc::invalid_argument);
  EXPECT_EQ(SharedMemory::open_existing("/").error().code, Errc::invalid_argument);
  EXPECT_EQ(SharedMemory::create_exclusive("/rescue-zero", 0).error().code, Errc::invalid_argument);
}

}  // namespace
}  // namespace rescue::hal
