// Issue 35, item 1: `bench fig4 --out DIR` wrote with fopen(path, "w") into any directory, so a user
// who made the directory (the default /tmp/rescue-fig4 is a fixed name anyone can create first) could
// point fig4.csv at root's files, or put a FIFO at fig4-summary.csv and hang it for good. Now --out
// must be a directory of this user or root that no one else may write (refused before measuring), and
// each file is created there by the descriptor of that directory, never through a link, never
// anything but a regular file (hal/files/trusted_file.hpp).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_directory.hpp"

namespace rescue {
namespace {

const std::string kProgram = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";
constexpr uid_t kNobody = 65534;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

using BenchFig4Out = testing::TempDirectoryTest;

// `timeout`: before, the FIFO case never ended.
test::CommandOutput fig4(const std::string& out) {
  return test::run_command("timeout 300 '" + kProgram + "' bench fig4 --periods 50 --load none --no-plot --out '" + out + "' 2>&1");
}

TEST_F(BenchFig4Out, AnotherUsersDirectoryIsRefusedBeforeMeasuringAndNothingIsWrittenThroughItsLinks) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to make a directory owned by nobody (uid 65534)";
  const std::string secret = dir_ + "/secret";
  std::ofstream(secret) << "root's secret";
  ASSERT_EQ(::chmod(secret.c_str(), 0600), 0);
  // What nobody does: mkdir -m777 x; ln -s /root/secret x/fig4.csv
  const std::string x = dir_ + "/x";
  ASSERT_EQ(::mkdir(x.c_str(), 0700), 0);
  ASSERT_EQ(::chmod(x.c_str(), 0777), 0);
  ASSERT_EQ(::symlink(secret.c_str(), (x + "/fig4.csv").c_str()), 0);
  ASSERT_EQ(::lchown((x + "/fig4.csv").c_str(), kNobody, kNobody), 0);
  ASSERT_EQ(::chown(x.c_str(), kNobody, kNobody), 0);
  const test::CommandOutput run = fig4(x);
  EXPECT_EQ(run.exit_status, 1) << run.out;
  EXPECT_TRUE(has(run.out, "--out: directory " + x + " is owned by uid 65534")) << run.out;
  EXPECT_FALSE(has(run.out, "periods_per_case")) << "refused before measuring: " << run.out;
  EXPECT_EQ(read(secret), "root's secret");
}

TEST_F(BenchFig4Out, AFifoAtAnOutputNameIsRefusedNotWaitedOn) {
  const std::string out = dir_ + "/out";
  ASSERT_EQ(::mkdir(out.c_str(), 0755), 0);
  ASSERT_EQ(::mkfifo((out + "/fig4-summary.csv").c_str(), 0644), 0);
  const test::CommandOutput run = fig4(out);
  EXPECT_EQ(run.exit_status, 1) << "124: it hung on the FIFO until timeout killed it\n" << run.out;
  EXPECT_TRUE(has(run.out, out + "/fig4-summary.csv is a FIFO")) << run.out;
  struct stat st {};
  EXPECT_EQ(::stat((out + "/fig4.csv").c_str(), &st), 0) << "the series before it is written";
}

}  // namespace
}  // namespace rescue
