// `rescue-motion run` end to end on the simulated robot (design brief section 6, issue 6):
//   run --scenario link-cut --state-dir DIR   cuts l_elbow 1 s after OP, reconfigures, exits 0;
//   run --duration S --state-dir DIR          restores the lost joints from the file before bring-up;
//   a truncated, garbage, empty or huge file  starts safely and says why the file was not used;
//   run --clear-joint NAMES                   the operator's clear after a repair, logged and durable.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "tests/support/run_command.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

const std::string kBinary = std::string(RESCUE_BINARY_DIR) + "/rescue-motion";

test::CommandOutput run(const std::string& arguments) { return test::run_command(kBinary + " run " + arguments + " 2>&1"); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(RunCommand, LinkCutScenarioReconfiguresThenARestartRestoresTheLostJoints) {
  testing::TempStateDir dir;
  const test::CommandOutput first = run("--scenario link-cut --state-dir " + dir.path);
  EXPECT_EQ(first.exit_status, 0) << first.out;
  EXPECT_TRUE(contains(first.out, "scenario link-cut: cut the link into l_elbow")) << first.out;
  EXPECT_TRUE(contains(first.out, "reconfiguration step 3 wrote the error-joints file: l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand"))
      << first.out;
  EXPECT_TRUE(contains(first.out, "l_elbow: Enabled --comm_lost--> Error")) << first.out;
  EXPECT_TRUE(contains(first.out, "healthy joints missed 0 cycles")) << first.out;
  EXPECT_TRUE(contains(first.out, "scenario link-cut passed")) << first.out;

  const test::CommandOutput second = run("--duration 0.3 --state-dir " + dir.path);
  EXPECT_EQ(second.exit_status, 0) << second.out;
  const std::size_t restored = second.out.find("restored lost joints l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand");
  const std::size_t bring_up = second.out.find("bringing the EtherCAT network up");
  ASSERT_NE(restored, std::string::npos) << second.out;
  ASSERT_NE(bring_up, std::string::npos) << second.out;
  EXPECT_LT(restored, bring_up) << "the file must be read before the network comes up";
}

TEST(RunCommand, OperatorClearsRepairedJointsAndTheNextStartRestoresNone) {
  testing::TempStateDir dir;
  const test::CommandOutput cut = run("--scenario link-cut --state-dir " + dir.path);
  ASSERT_EQ(cut.exit_status, 0) << cut.out;

  // Repaired (the simulated robot starts whole): the operator clears the four joints.
  const test::CommandOutput cleared =
      run("--duration 0.5 --initialize --clear-joint l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand,neck_pan --state-dir " + dir.path);
  EXPECT_EQ(cleared.exit_status, 0) << cleared.out;
  EXPECT_TRUE(contains(cleared.out, "--clear-joint: neck_pan not recorded lost; nothing to clear")) << cleared.out;
  EXPECT_TRUE(contains(cleared.out, "operator declares l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand repaired")) << cleared.out;
  EXPECT_TRUE(contains(cleared.out, "l_elbow: cleared by operator after repair")) << cleared.out;
  EXPECT_TRUE(contains(cleared.out, "l_hand: Error --reset--> Idle")) << cleared.out;
  EXPECT_TRUE(contains(cleared.out, "l_hand: Ready --enable--> Enabled")) << cleared.out;
  EXPECT_TRUE(contains(cleared.out, "lost joints: none")) << cleared.out;

  const test::CommandOutput next = run("--duration 0.2 --state-dir " + dir.path);
  EXPECT_EQ(next.exit_status, 0) << next.out;
  EXPECT_FALSE(contains(next.out, "restored lost joints")) << next.out;
}

TEST(RunCommand, ClearingAJointBehindOneThatStaysLostIsRefusedAndTheFileKept) {
  testing::TempStateDir dir;
  const test::CommandOutput cut = run("--scenario link-cut --state-dir " + dir.path);
  ASSERT_EQ(cut.exit_status, 0) << cut.out;
  const test::CommandOutput refused = run("--duration 0.2 --clear-joint l_elbow,l_hand --state-dir " + dir.path);
  EXPECT_EQ(refused.exit_status, 1) << refused.out;
  EXPECT_TRUE(contains(refused.out, "--clear-joint: l_hand cannot answer behind l_wrist_yaw,l_wrist_pitch")) << refused.out;
  EXPECT_FALSE(contains(refused.out, "bringing the EtherCAT network up")) << refused.out;
  const test::CommandOutput next = run("--duration 0.2 --state-dir " + dir.path);
  EXPECT_TRUE(contains(next.out, "restored lost joints l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand")) << next.out;
}

TEST(RunCommand, UnknownJointToClearIsRefusedBeforeAnythingStarts) {
  testing::TempStateDir dir;
  const test::CommandOutput out = run("--clear-joint l_elbow,tail --state-dir " + dir.path);
  EXPECT_EQ(out.exit_status, 1) << out.out;
  EXPECT_TRUE(contains(out.out, "--clear-joint 'l_elbow,tail': unknown joint name in the list (item 2)")) << out.out;
  EXPECT_FALSE(contains(out.out, "bringing the EtherCAT network up")) << out.out;
}

void expect_safe_start_with(const std::string& bytes, const std::string& why) {
  testing::TempStateDir dir;
  {
    std::ofstream file(dir.file(), std::ios::binary);
    file << bytes;
  }
  const test::CommandOutput out = run("--duration 0.2 --state-dir " + dir.path);
  // No second copy beside it: no readable record, so every joint is held in Error until cleared by
  // name (issue 35 item 12) and the run ends "the robot ended in error", exit status 3.
  EXPECT_EQ(out.exit_status, 3) << out.out;
  EXPECT_TRUE(contains(out.out, "error-joints file not used: " + why)) << out.out;
  EXPECT_TRUE(contains(out.out, "no readable record of the lost joints")) << out.out;
  EXPECT_TRUE(contains(out.out, "network in OP")) << out.out;
}

TEST(RunCommand, EmptyErrorFileStartsSafely) { expect_safe_start_with("", "file is empty"); }
TEST(RunCommand, GarbageErrorFileStartsSafely) { expect_safe_start_with(std::string(200, '\x5a'), "not an error-joints file"); }
TEST(RunCommand, TruncatedErrorFileStartsSafely) {
  // A valid header announcing records that are not there.
  testing::TempStateDir source;
  const test::CommandOutput cut = run("--scenario link-cut --state-dir " + source.path);
  ASSERT_EQ(cut.exit_status, 0) << cut.out;
  std::ifstream in(source.file(), std::ios::binary);
  const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(whole.size(), 40u);
  expect_safe_start_with(whole.substr(0, 40), "file shorter than its record count");
}
TEST(RunCommand, HugeErrorFileStartsSafely) { expect_safe_start_with(std::string(1 << 20, '\0'), "file larger than the read cap"); }

}  // namespace
}  // namespace rescue::app
