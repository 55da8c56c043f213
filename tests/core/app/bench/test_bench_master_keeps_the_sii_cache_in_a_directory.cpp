// `bench master --sii-cache-dir DIR` keeps the master's SII cache in DIR/sii-cache as `run` keeps it
// in its state directory (docs/master.md "SII cache"): the first bring-up reads every image whole
// and writes the file, the next one finds all 23 slaves in it; `--cold-start no` measures bring-up
// and the cycles only (toolchain/compare-with-soem.sh), anything but yes/no is refused.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdlib>
#include <string>

#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(BenchMasterSiiCache, TheSecondBringUpFindsEverySlaveInTheDirectorysCache) {
  char dir[] = "/tmp/bench-sii-cache.XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  const std::string file = std::string(dir) + "/sii-cache";
  const std::string command = kBinary + " bench master --cycles 100 --cold-start no --sii-cache-dir " + dir + " 2>&1";

  const test::CommandOutput first = test::run_command(command);
  EXPECT_EQ(first.exit_status, 0) << first.out;
  struct stat st {};
  ASSERT_EQ(stat(file.c_str(), &st), 0) << "no cache file written";
  EXPECT_GT(st.st_size, 23 * 32);
  EXPECT_TRUE(contains(first.out, "sii_cache_hits: 0 of 23 slaves")) << first.out;
  EXPECT_FALSE(contains(first.out, "dc_cold_cycles_to_20ns:")) << "--cold-start no skips the cold start";

  const test::CommandOutput second = test::run_command(command);
  EXPECT_EQ(second.exit_status, 0) << second.out;
  EXPECT_TRUE(contains(second.out, "sii_cache_hits: 23 of 23 slaves")) << second.out;
  (void)std::remove(file.c_str());
  (void)rmdir(dir);
}

TEST(BenchMasterSiiCache, ColdStartTakesOnlyYesOrNo) {
  const test::CommandOutput out = test::run_command(kBinary + " bench master --cold-start maybe 2>&1");
  EXPECT_NE(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "--cold-start must be yes or no")) << out.out;
}

}  // namespace
}  // namespace rescue::app
