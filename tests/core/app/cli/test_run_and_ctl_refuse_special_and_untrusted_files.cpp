// `rescue-motion run` and `ctl` as a user runs them (docs/security.md): a FIFO, a directory or a
// device given as any file argument (--key, --config, --capture, --timing-out, a FIFO at the state
// directory's lock) makes the command exit non-zero within 2 s naming the path and what is there; and
// StrictModes: a key file, a configuration file or a state directory that another user owns or may
// write is refused with the path and the fix, by run and by ctl, a link only followed to a trusted
// target. The other-user cases need root (chown to nobody); without it they are skipped, saying why.
// Each command runs under `timeout -s KILL 10`: the old behaviour (a hang in open()) fails the test
// instead of hanging it.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::run_program;
using testing::TempStateDir;

constexpr unsigned kNobody = 65534;

struct Timed {
  CommandResult result;
  double seconds{0};
};

Timed timed(const std::vector<std::string>& args) {
  std::vector<std::string> all{"timeout", "-s", "KILL", "10", testing::rescue_binary()};
  all.insert(all.end(), args.begin(), args.end());
  std::string line;
  for (const std::string& a : all) line += "'" + a + "' ";
  line += "2>&1";
  Timed t;
  const auto t0 = std::chrono::steady_clock::now();
  FILE* p = ::popen(line.c_str(), "r");
  if (p == nullptr) return t;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, p)) > 0) t.result.out.append(buffer, n);
  const int status = ::pclose(p);
  t.result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return t;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void write_file(const std::string& path, const std::string& text, mode_t mode) {
  FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_NE(f, nullptr) << path;
  (void)std::fputs(text.c_str(), f);
  (void)std::fclose(f);
  ASSERT_EQ(::chmod(path.c_str(), mode), 0);
}

class SpecialFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    fifo_ = dir_.path + "/fifo";
    ASSERT_EQ(::mkfifo(fifo_.c_str(), 0600), 0);
    sub_ = dir_.path + "/sub";
    ASSERT_EQ(::mkdir(sub_.c_str(), 0700), 0);
    state_ = dir_.path + "/state";
    ASSERT_EQ(::mkdir(state_.c_str(), 0700), 0);
    key_ = dir_.path + "/operator.key";
    ASSERT_EQ(run_program({"ctl", "keygen", "--key", key_}).status, 0);
  }
  // What each kind of special file is called in the refusal.
  struct Kind {
    std::string path;
    const char* says;
  };
  std::vector<Kind> kinds() const { return {{fifo_, "FIFO"}, {sub_, "directory"}, {"/dev/null", "character device"}}; }
  void expect_refused_fast(const std::vector<std::string>& args, const Kind& kind) {
    const Timed t = timed(args);
    std::string line;
    for (const std::string& a : args) line += a + " ";
    EXPECT_NE(t.result.status, 0) << line << "\n" << t.result.out;
    EXPECT_LT(t.seconds, 2.0) << line;
    EXPECT_TRUE(has(t.result.out, kind.says)) << line << "\n" << t.result.out;
  }
  TempStateDir dir_;
  std::string fifo_, sub_, state_, key_;
};

TEST_F(SpecialFiles, RunExitsWithinTwoSecondsNamingAFifoADirectoryOrADeviceAsAnyFileArgument) {
  for (const Kind& k : kinds()) {
    expect_refused_fast({"run", "--state-dir", state_, "--key", k.path, "--duration", "1"}, k);
    expect_refused_fast({"run", "--state-dir", state_, "--config", k.path, "--duration", "1"}, k);
    expect_refused_fast({"run", "--state-dir", state_, "--key", key_, "--capture", k.path, "--duration", "1"}, k);
  }
  // --timing-out names a directory: a FIFO or a device there is refused before the run, not after.
  for (const std::string& not_dir : {fifo_, std::string("/dev/null")}) {
    expect_refused_fast({"run", "--state-dir", state_, "--timing-out", not_dir, "--duration", "1"},
                        Kind{not_dir, "not a directory"});
  }
}

TEST_F(SpecialFiles, RunRefusesAFifoAtTheStateDirectorysLockWithinTwoSeconds) {
  ASSERT_EQ(::mkfifo((state_ + "/rescue-motion.lock").c_str(), 0600), 0);
  const Timed t = timed({"run", "--state-dir", state_, "--duration", "1"});
  EXPECT_NE(t.result.status, 0) << t.result.out;
  EXPECT_LT(t.seconds, 2.0);
  EXPECT_TRUE(has(t.result.out, "not a regular file")) << t.result.out;
}

TEST_F(SpecialFiles, CtlExitsWithinTwoSecondsNamingAFifoADirectoryOrADeviceAsItsKey) {
  for (const Kind& k : kinds()) {
    expect_refused_fast({"ctl", "--key", k.path, "--timeout", "1", "status"}, k);
  }
  // Nothing answers at this port: ctl gives up at its --timeout (0.3 s) with the reason.
  const Timed t = timed({"ctl", "--key", key_, "--port", std::to_string(testing::free_udp_port()), "--timeout", "0.3", "status"});
  EXPECT_NE(t.result.status, 0);
  EXPECT_LT(t.seconds, 2.0);
  EXPECT_TRUE(has(t.result.out, "no authentic answer")) << t.result.out;
}

class Ownership : public SpecialFiles {
 protected:
  void SetUp() override {
    if (::geteuid() != 0) GTEST_SKIP() << "needs root to chown files to nobody (uid 65534)";
    SpecialFiles::SetUp();
  }
};

TEST_F(Ownership, RunRefusesAKeyAConfigurationOrAStateDirectoryAnotherUserOwnsOrMayWrite) {
  // A key of nobody's, even with mode 0600.
  const std::string foreign_key = dir_.path + "/foreign.key";
  ASSERT_EQ(run_program({"ctl", "keygen", "--key", foreign_key}).status, 0);
  ASSERT_EQ(::chown(foreign_key.c_str(), kNobody, kNobody), 0);
  Timed t = timed({"run", "--state-dir", state_, "--key", foreign_key, "--duration", "1"});
  EXPECT_EQ(t.result.status, 1) << t.result.out;
  EXPECT_TRUE(has(t.result.out, foreign_key + " is owned by uid 65534")) << t.result.out;

  // A link of ours to that key: followed only to a trusted target, so refused too.
  const std::string link = dir_.path + "/link.key";
  ASSERT_EQ(::symlink(foreign_key.c_str(), link.c_str()), 0);
  t = timed({"run", "--state-dir", state_, "--key", link, "--duration", "1"});
  EXPECT_EQ(t.result.status, 1) << t.result.out;
  EXPECT_TRUE(has(t.result.out, "owned by uid 65534")) << t.result.out;

  // The case: a mode-0666 configuration of nobody's naming a key.
  const std::string conf = dir_.path + "/robot.conf";
  write_file(conf, "key_file = " + key_ + "\n", 0666);
  ASSERT_EQ(::chown(conf.c_str(), kNobody, kNobody), 0);
  t = timed({"run", "--state-dir", state_, "--config", conf, "--duration", "1"});
  EXPECT_EQ(t.result.status, 1) << t.result.out;
  EXPECT_TRUE(has(t.result.out, conf + " is owned by uid 65534")) << t.result.out;
  ASSERT_EQ(::chown(conf.c_str(), 0, 0), 0);
  t = timed({"run", "--state-dir", state_, "--config", conf, "--duration", "1"});
  EXPECT_EQ(t.result.status, 1) << t.result.out;
  EXPECT_TRUE(has(t.result.out, "writable by group or others (mode 0666)")) << t.result.out;
  EXPECT_TRUE(has(t.result.out, "chmod go-w " + conf)) << t.result.out;

  // A state directory anyone may write (the mode-0777 directory), and one of nobody's.
  ASSERT_EQ(::chmod(state_.c_str(), 0777), 0);
  t = timed({"run", "--state-dir", state_, "--duration", "1"});
  EXPECT_EQ(t.result.status, 1) << t.result.out;
  EXPECT_TRUE(has(t.result.out, "state directory refused")) << t.result.out;
  EXPECT_TRUE(has(t.result.out, "chmod go-w " + state_)) << t.result.out;
  ASSERT_EQ(::chmod(state_.c_str(), 0700), 0);
  ASSERT_EQ(::chown(state_.c_str(), kNobody, kNobody), 0);
  t = timed({"run", "--state-dir", state_, "--duration", "1"});
  EXPECT_EQ(t.result.status, 1) << t.result.out;
  EXPECT_TRUE(has(t.result.out, state_ + " is owned by uid 65534")) << t.result.out;
  // Root's and sticky, mode 1777 (as /tmp): passes on the way to a directory, not as the state
  // directory itself, where anyone could take the lock or plant the error-joints file first.
  ASSERT_EQ(::chown(state_.c_str(), 0, 0), 0);
  ASSERT_EQ(::chmod(state_.c_str(), 01777), 0);
  t = timed({"run", "--state-dir", state_, "--duration", "1"});
  EXPECT_EQ(t.result.status, 1) << t.result.out;
  EXPECT_TRUE(has(t.result.out, "state directory refused: state directory " + state_ + " is shared")) << t.result.out;
}

TEST_F(Ownership, CtlRefusesAKeyAnotherUserOwnsOrThatLiesInADirectoryOthersMayWrite) {
  const std::string foreign_key = dir_.path + "/foreign.key";
  ASSERT_EQ(run_program({"ctl", "keygen", "--key", foreign_key}).status, 0);
  ASSERT_EQ(::chown(foreign_key.c_str(), kNobody, kNobody), 0);
  Timed t = timed({"ctl", "--key", foreign_key, "--timeout", "0.5", "status"});
  EXPECT_EQ(t.result.status, 4) << t.result.out;
  EXPECT_TRUE(has(t.result.out, foreign_key + " is owned by uid 65534")) << t.result.out;

  const std::string open_dir = dir_.path + "/open";
  ASSERT_EQ(::mkdir(open_dir.c_str(), 0700), 0);
  const std::string key = open_dir + "/operator.key";
  ASSERT_EQ(run_program({"ctl", "keygen", "--key", key}).status, 0);
  ASSERT_EQ(::chmod(open_dir.c_str(), 0777), 0);
  t = timed({"ctl", "--key", key, "--timeout", "0.5", "status"});
  EXPECT_EQ(t.result.status, 4) << t.result.out;
  EXPECT_TRUE(has(t.result.out, "directory " + open_dir + " is writable by group or others")) << t.result.out;
}

}  // namespace
}  // namespace rescue::app
