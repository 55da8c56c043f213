// The state directory: --state-dir wins, root gets /var/lib/rescue-motion, other users a per-user
// directory ($XDG_STATE_HOME when absolute, else ~/.local/state), created when missing.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdlib>
#include <string>

#include "hal/files/state_dir.hpp"

namespace rescue::hal {
namespace {

std::string chosen(const char* option, bool privileged, const char* xdg, const char* home) {
  auto dir = choose_state_dir(option, privileged, xdg, home);
  return dir.ok() ? std::string(dir.value().path.c_str()) + " <- " + dir.value().source : std::string("ERROR");
}

TEST(StateDir, OptionWinsOverEverything) {
  EXPECT_EQ(chosen("/tmp/s", true, "/x", "/home/u"), "/tmp/s <- --state-dir");
  EXPECT_EQ(chosen("rel/dir", false, nullptr, nullptr), "rel/dir <- --state-dir");
  EXPECT_EQ(chosen("", false, nullptr, "/home/u"), "ERROR");
}

TEST(StateDir, RootUsesTheSystemDirectory) {
  EXPECT_EQ(chosen(nullptr, true, "/x", "/root"), "/var/lib/rescue-motion <- system default");
}

TEST(StateDir, UsersGetXdgStateHomeOrHomeLocalState) {
  EXPECT_EQ(chosen(nullptr, false, "/home/u/.st", "/home/u"), "/home/u/.st/rescue-motion <- $XDG_STATE_HOME");
  EXPECT_EQ(chosen(nullptr, false, nullptr, "/home/u"), "/home/u/.local/state/rescue-motion <- $HOME");
  EXPECT_EQ(chosen(nullptr, false, "relative", "/home/u"), "/home/u/.local/state/rescue-motion <- $HOME");
  EXPECT_EQ(chosen(nullptr, false, "", "/home/u"), "/home/u/.local/state/rescue-motion <- $HOME");
}

// Root gets the system directory only as the installed program: a build run from the source tree (as
// this test is) keeps its state per user, so it never leaves root's files in the package's directory.
TEST(StateDir, OnlyTheInstalledProgramDefaultsToTheSystemDirectory) {
  EXPECT_TRUE(is_installed_program_path("/usr/bin/rescue-motion"));
  EXPECT_FALSE(is_installed_program_path("/work/rescue-motion/build/release/rescue-motion"));
  EXPECT_FALSE(is_installed_program_path("/usr"));
  EXPECT_FALSE(is_installed_program_path(nullptr));
  EXPECT_FALSE(system_state_dir_is_default()) << "this test runs from the build tree";
  const char* home = std::getenv("HOME");  // NOLINT(concurrency-mt-unsafe)
  if (home != nullptr && home[0] == '/') {
    auto dir = resolve_state_dir(nullptr);
    ASSERT_TRUE(dir.ok()) << dir.error().what;
    EXPECT_STRNE(dir.value().path.c_str(), kSystemStateDir);
  }
}

TEST(StateDir, UserWithoutHomeGetsAClearError) {
  auto dir = choose_state_dir(nullptr, false, nullptr, nullptr);
  ASSERT_FALSE(dir.ok());
  EXPECT_EQ(dir.error().code, Errc::not_found);
}

TEST(StateDir, ResolveCreatesTheDirectory) {
  std::string base = ::testing::TempDir() + "statedir-XXXXXX";
  ASSERT_NE(mkdtemp(base.data()), nullptr);
  const std::string wanted = base + "/a/b";
  auto dir = resolve_state_dir(wanted.c_str());
  ASSERT_TRUE(dir.ok()) << dir.error().what;
  struct stat st {};
  EXPECT_EQ(stat(wanted.c_str(), &st), 0);
  EXPECT_TRUE(S_ISDIR(st.st_mode));
  (void)std::system(("rm -rf '" + base + "'").c_str());
}

}  // namespace
}  // namespace rescue::hal
