// Issue 21 item 2, end to end: `rescue-motion run --scenario link-cut` with the real error-joints file
// on a slow disk (tests/support/slow_disk_shim.cpp under LD_PRELOAD: every fsync waits 1 s, so the
// file's durable write takes 2 s). The joint manager's period never contains the write: its longest
// period stays below one delayed fsync, the scenario passes (the joints behind the cut are lost, the
// healthy ones missed no cycle), and the file read back from the disk afterwards holds the lost joints.
// In both task modes: processes (the default) and --threads.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
constexpr long kFsyncDelayMs = 1000;
const JointMask kElbowCut = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));

// The value of a `key: value` summary line, or -1.
long long summary_value(const std::string& out, const std::string& key) {
  const std::string prefix = "\n" + key + ": ";
  const std::size_t at = out.find(prefix);
  if (at == std::string::npos) return -1;
  return std::atoll(out.c_str() + at + prefix.size());
}

int lines_in(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

void link_cut_on_a_slow_disk(const std::string& mode) {
  testing::TempStateDir dir;
  const std::string slow_log = dir.path + "/../" + "slow-disk-" + std::to_string(::getpid()) + mode + ".log";
  const test::CommandOutput out = test::run_command(
      "LD_PRELOAD=" RESCUE_SLOW_DISK_SHIM " RESCUE_SLOW_DISK_MS=" + std::to_string(kFsyncDelayMs) +
      " RESCUE_SLOW_DISK_LOG=" + slow_log + " ASAN_OPTIONS=verify_asan_link_order=0 " + kBinary +
      " run --scenario link-cut " + mode + " --state-dir " + dir.path + " 2>&1");
  EXPECT_EQ(out.exit_status, 0) << out.out;  // the scenario's verdict: lost joints, no healthy miss, file current
  EXPECT_GE(lines_in(slow_log), 2) << "the shim did not delay the write's fsyncs";
  (void)std::remove(slow_log.c_str());

  // The joint manager's longest period held no fsync (each one waited kFsyncDelayMs).
  const long long longest = summary_value(out.out, "max_execution_ns_joint_manager");
  ASSERT_GE(longest, 0) << out.out;
  EXPECT_LT(longest, kFsyncDelayMs * 1'000'000LL) << out.out;

  // Durable: read back from the disk after the run.
  ErrorJointsFileStorage files(dir.path.c_str());
  const ErrorJointsLoad load = files.load();
  ASSERT_TRUE(load.file_present) << out.out;
  EXPECT_TRUE(load.decoded.status.ok());
  EXPECT_EQ(load.decoded.contents.joints(), kElbowCut);
}

TEST(RunCommandOnASlowDisk, LinkCutInProcessesModeNeverWaitsForTheDisk) { link_cut_on_a_slow_disk(""); }

TEST(RunCommandOnASlowDisk, LinkCutInThreadsModeNeverWaitsForTheDisk) { link_cut_on_a_slow_disk("--threads"); }

}  // namespace
}  // namespace rescue::app
