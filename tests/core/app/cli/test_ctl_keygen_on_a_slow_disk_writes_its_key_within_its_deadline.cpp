// `ctl keygen` waits for no robot, only for its key to reach the disk, so its default deadline is
// 10 s (docs/operator.md, `ctl --help`), not the 2 s meant for a robot's answer. On a slow disk
// (tests/support/slow_disk_shim.cpp under LD_PRELOAD: every fsync waits 1.5 s, as a disk under heavy
// write-back does) it still writes its key: exit status 0, a 32-byte key file of mode 0600, and the
// shim's log shows its fsyncs really waited. With --timeout 1 the same disk makes it stop with a
// clear error (exit status not 0) instead of hanging, and leaves no key file behind.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_directory.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
constexpr int kFsyncDelayMs = 1500;  // 2 s would already pass the robot's 2 s deadline alone

int lines_in(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

// keygen with every fsync held kFsyncDelayMs, its key in a fresh directory, each held fsync logged.
struct SlowDiskKeygen : testing::TempDirectoryTest {
  test::CommandOutput keygen(const std::string& extra) {
    return test::run_command("LD_PRELOAD=" RESCUE_SLOW_DISK_SHIM " RESCUE_SLOW_DISK_MS=" + std::to_string(kFsyncDelayMs) +
                             " RESCUE_SLOW_DISK_LOG=" + log() + " ASAN_OPTIONS=verify_asan_link_order=0 " + kBinary +
                             " ctl keygen --key " + key() + extra + " 2>&1");
  }
  std::string key() const { return path("operator.key"); }
  std::string log() const { return path("slow-disk.log"); }
};

TEST_F(SlowDiskKeygen, WritesItsKeyWithinItsDefaultDeadline) {
  const test::CommandOutput out = keygen("");
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_GE(lines_in(log()), 1) << "the shim did not delay keygen's fsync\n" << out.out;
  struct stat st {};
  ASSERT_EQ(::stat(key().c_str(), &st), 0) << out.out;
  EXPECT_EQ(st.st_mode & 0777, 0600U) << out.out;
  std::ifstream in(key());
  std::string hex;
  std::getline(in, hex);
  EXPECT_EQ(hex.size(), 64U) << "32 bytes as hex";
  EXPECT_EQ(hex.find_first_not_of("0123456789abcdef"), std::string::npos) << hex;
}

TEST_F(SlowDiskKeygen, AShorterTimeoutStopsItWithAnErrorAndNoKeyFile) {
  const test::CommandOutput out = keygen(" --timeout 1");
  EXPECT_NE(out.exit_status, 0) << out.out;
  EXPECT_NE(out.out.find("--timeout"), std::string::npos) << "the error says why\n" << out.out;
  struct stat st {};
  EXPECT_NE(::stat(key().c_str(), &st), 0) << "no key file: the key did not reach the disk, none is claimed";
}

}  // namespace
}  // namespace rescue::app
