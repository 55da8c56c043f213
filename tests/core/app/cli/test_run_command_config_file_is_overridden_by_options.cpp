// `rescue-motion run --config FILE` (docs/configuration.md) as a user runs it: the file's settings are
// used, an option on the command line overrides the file, a bad file stops the run before the network
// with FILE:LINE, the key and the allowed range, and `run --config FILE --check` reads the file too.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <string>

#include "tests/support/run_command.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

test::CommandOutput run(const std::string& arguments) { return test::run_command(kBinary + " " + arguments + " 2>&1"); }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class RunConfig : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = "/tmp/rescue-config-test-" + std::to_string(::getpid());
    ASSERT_EQ(test::run_command("rm -rf " + dir_ + " && mkdir -p " + dir_ + "/file " + dir_ + "/option").exit_status, 0);
  }
  void TearDown() override { (void)test::run_command("rm -rf " + dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = dir_ + "/" + name;
    std::FILE* f = std::fopen(path.c_str(), "w");
    EXPECT_NE(f, nullptr);
    if (f != nullptr) {
      (void)std::fputs(text.c_str(), f);
      (void)std::fclose(f);
    }
    return path;
  }
  std::string dir_;
};

TEST_F(RunConfig, OptionsOverrideTheFile) {
  // The file says: run a week, state in file/; the command line says 0.3 s, state in option/.
  const std::string conf = write("a.conf", "nic = sim\nduration = 604800\nstate_dir = " + dir_ + "/file\n");
  const test::CommandOutput out = run("run --config " + conf + " --duration 0.3 --state-dir " + dir_ + "/option");
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "state directory " + dir_ + "/option (--state-dir)")) << out.out;
  EXPECT_TRUE(contains(out.out, "run: privileges: ")) << out.out;
}

TEST_F(RunConfig, TheFileIsUsedWithoutOptions) {
  const std::string conf = write("b.conf", "duration = 0.3\nstate_dir = " + dir_ + "/file\n");
  const test::CommandOutput out = run("run --config " + conf);
  EXPECT_EQ(out.exit_status, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "state directory " + dir_ + "/file")) << out.out;
}

TEST_F(RunConfig, ABadFileStopsBeforeTheNetworkNamingLineKeyAndRange) {
  const std::string conf = write("c.conf", "nic = sim\n\n[joint_manager]\ncpu = 4096\n");
  const test::CommandOutput out = run("run --config " + conf + " --duration 0.3");
  EXPECT_EQ(out.exit_status, 1) << out.out;
  EXPECT_TRUE(contains(out.out, "rescue-motion run: --config " + conf + ":4: key 'cpu': CPU out of range (allowed: 0..1023)"))
      << out.out;
  EXPECT_FALSE(contains(out.out, "bringing the EtherCAT network up")) << out.out;
}

TEST_F(RunConfig, CheckReadsTheFile) {
  const std::string conf = write("d.conf", "nic = sim\nspeed = 3\n");
  const test::CommandOutput bad = run("run --config " + conf + " --check");
  EXPECT_EQ(bad.exit_status, 1) << bad.out;
  EXPECT_TRUE(contains(bad.out, ":2: key 'speed': unknown key")) << bad.out;
  const std::string good = write("e.conf", "nic = sim\n");
  const test::CommandOutput ok = run("run --config " + good + " --check");
  EXPECT_EQ(ok.exit_status, 0) << ok.out;
  EXPECT_TRUE(contains(ok.out, "rescue-motion run --check: OK: nic sim")) << ok.out;
}

}  // namespace
}  // namespace rescue::app
