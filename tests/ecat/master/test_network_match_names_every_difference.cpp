// Comparing a found network with the robot's plan: a perfect network is operated whole, and each
// kind of difference (missing, extra, wrong device, wrong position, duplicate alias, process data
// size, revision, known-lost joints) is named with the right positions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/master/network_match.hpp"

namespace rescue::ecat {
namespace {

using drivers::kRobotNetworkPlan;

FoundSlave device_for(std::size_t planned) {
  const SlavePlan& s = kRobotNetworkPlan[planned];
  FoundSlave f;
  f.vendor_id = s.vendor_id;
  f.product_code = s.product_code;
  f.revision = s.revision;
  f.serial_number = 1000 + static_cast<std::uint32_t>(planned);
  f.station_alias = s.station_alias;
  f.output_bits = 8U * s.output_bytes;
  f.input_bits = 8U * s.input_bytes;
  f.pdo_sizes_known = true;
  std::strncpy(f.name.data(), s.device_name, f.name.size() - 1);
  return f;
}

std::vector<FoundSlave> robot() {
  std::vector<FoundSlave> found;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) found.push_back(device_for(p));
  return found;
}

NetworkMatch match(const std::vector<FoundSlave>& found, JointMask lost = 0) {
  return match_network(kRobotNetworkPlan, Span<const FoundSlave>(found.data(), found.size()), drivers::slaves_of_joints(lost));
}

std::string lines(const NetworkMatch& m, const std::vector<FoundSlave>& found) {
  std::string all;
  char line[256];
  for (const NetworkDifference& d : m.differences) {
    describe(d, kRobotNetworkPlan, Span<const FoundSlave>(found.data(), found.size()), line, sizeof line);
    all += line;
    all += '\n';
  }
  return all;
}

TEST(NetworkMatch, TheRobotAsPlannedIsOperatedWhole) {
  const auto found = robot();
  const NetworkMatch m = match(found);
  EXPECT_FALSE(m.fatal) << lines(m, found);
  EXPECT_TRUE(m.differences.empty()) << lines(m, found);
  EXPECT_EQ(m.operated, kAllSlaves);
  for (std::size_t p = 0; p < kMaxSlaves; ++p) EXPECT_EQ(m.found_of_slot[p], p);
}

TEST(NetworkMatch, MissingTailOfABranchIsNamedAndLaterSlavesKeepTheirSlots) {
  auto found = robot();
  found.erase(found.begin() + 5, found.begin() + 9);  // r_elbow .. r_hand
  const NetworkMatch m = match(found);
  EXPECT_TRUE(m.fatal);
  ASSERT_EQ(m.count(DifferenceKind::missing), 4u) << lines(m, found);
  EXPECT_EQ(m.differences.size(), 4u) << lines(m, found);  // the shift is not "wrong position"
  EXPECT_EQ(m.found_of_slot[9], 5u);                        // l_leg answers at position 5, operated as 9
  EXPECT_NE(lines(m, found).find("missing: r_elbow (position 5"), std::string::npos) << lines(m, found);
}

TEST(NetworkMatch, KnownLostJointsAreNotADifferenceAndTheRestRuns) {
  auto found = robot();
  found.erase(found.begin() + 5, found.begin() + 9);
  const JointMask lost = joints_lost_by_link_failure_at(joint_index_by_name("r_elbow"));
  const NetworkMatch m = match(found, lost);
  EXPECT_FALSE(m.fatal) << lines(m, found);
  EXPECT_TRUE(m.differences.empty()) << lines(m, found);
  EXPECT_EQ(drivers::joints_of_slaves(m.operated), kAllJoints & ~lost);
}

TEST(NetworkMatch, KnownLostJointThatAnswersIsAWarningAndStaysOut) {
  const auto found = robot();
  const JointMask lost = joint_bit(joint_index_by_name("r_hand"));
  const NetworkMatch m = match(found, lost);
  EXPECT_FALSE(m.fatal);
  EXPECT_EQ(m.count(DifferenceKind::known_lost_present), 1u);
  EXPECT_EQ(drivers::joints_of_slaves(m.operated), kAllJoints & ~lost);
}

TEST(NetworkMatch, ExtraDeviceIsNamed) {
  auto found = robot();
  FoundSlave stranger = device_for(22);
  stranger.station_alias = 0x2222;
  stranger.vendor_id = 2;
  found.push_back(stranger);
  const NetworkMatch m = match(found);
  EXPECT_TRUE(m.fatal);
  ASSERT_EQ(m.count(DifferenceKind::extra), 1u) << lines(m, found);
  EXPECT_EQ(m.differences[0].found, 23u);
  EXPECT_EQ(m.operated, kAllSlaves);
}

TEST(NetworkMatch, WrongDeviceInAJointsSlotIsNamed) {
  auto found = robot();
  found[13] = device_for(0);  // a junction where waist_yaw belongs...
  found[13].station_alias = kRobotNetworkPlan[13].station_alias;  // ...commissioned as waist_yaw
  const NetworkMatch m = match(found);
  EXPECT_TRUE(m.fatal);
  ASSERT_EQ(m.count(DifferenceKind::wrong_device), 1u) << lines(m, found);
  EXPECT_EQ(m.differences[0].planned, 13u);
  EXPECT_EQ(m.count(DifferenceKind::missing), 0u) << "a wrong device is not also missing";
  EXPECT_EQ(m.operated & slave_bit(13), 0u);
  EXPECT_NE(lines(m, found).find("wrong device: position 13 holds RM-JCT4"), std::string::npos) << lines(m, found);
}

TEST(NetworkMatch, SwappedCablesGiveWrongPosition) {
  auto found = robot();
  std::swap(found[3], found[4]);  // r_shoulder_roll and r_shoulder_yaw swapped
  const NetworkMatch m = match(found);
  EXPECT_TRUE(m.fatal);
  ASSERT_EQ(m.count(DifferenceKind::wrong_position), 1u) << lines(m, found);
  EXPECT_EQ(m.differences.size(), 1u) << lines(m, found);
}

TEST(NetworkMatch, ArmsPluggedIntoEachOthersPortsAreWrongPositions) {
  auto found = robot();
  // Left arm (planned 16..22) arrives before the torso (13..15).
  std::vector<FoundSlave> swapped(found.begin(), found.begin() + 13);
  swapped.insert(swapped.end(), found.begin() + 16, found.end());
  swapped.insert(swapped.end(), found.begin() + 13, found.begin() + 16);
  const NetworkMatch m = match(swapped);
  EXPECT_TRUE(m.fatal);
  EXPECT_EQ(m.count(DifferenceKind::wrong_position), 3u) << lines(m, swapped);  // the shorter run: torso
}

TEST(NetworkMatch, TwoDevicesWithOneAliasAreNamed) {
  auto found = robot();
  found[10].station_alias = found[9].station_alias;
  const NetworkMatch m = match(found);
  EXPECT_TRUE(m.fatal);
  EXPECT_EQ(m.count(DifferenceKind::duplicate_alias), 1u) << lines(m, found);
  EXPECT_EQ(m.count(DifferenceKind::missing), 1u) << lines(m, found);  // nobody is r_leg
}

TEST(NetworkMatch, OtherProcessDataSizeRefusesTheSlave) {
  auto found = robot();
  found[20].input_bits = 8 * 16;
  const NetworkMatch m = match(found);
  EXPECT_TRUE(m.fatal);
  EXPECT_EQ(m.count(DifferenceKind::process_data_size), 1u) << lines(m, found);
  EXPECT_EQ(m.operated & slave_bit(20), 0u);
}

TEST(NetworkMatch, OtherRevisionIsOnlyAWarning) {
  auto found = robot();
  found[7].revision = 0x00020000;
  const NetworkMatch m = match(found);
  EXPECT_FALSE(m.fatal);
  EXPECT_EQ(m.count(DifferenceKind::revision), 1u);
  EXPECT_EQ(m.operated, kAllSlaves);
}

TEST(NetworkMatch, WithoutAliasesDevicesAreMatchedByOrder) {
  auto found = robot();
  for (FoundSlave& f : found) f.station_alias = 0;
  EXPECT_EQ(match(found).operated, kAllSlaves);
  found.pop_back();  // l_hand gone
  const NetworkMatch m = match(found);
  EXPECT_EQ(m.count(DifferenceKind::missing), 1u) << lines(m, found);
  EXPECT_EQ(m.differences[0].planned, 22u);
  found.erase(found.begin() + 1);  // junction_b gone too: joints slide into the wrong device types? no: same type
  const NetworkMatch m2 = match(found);
  EXPECT_TRUE(m2.fatal);
  EXPECT_GE(m2.count(DifferenceKind::wrong_device), 1u) << lines(m2, found);  // a joint where junction_b belongs
}

TEST(NetworkMatch, EmptyNetworkIsEverySlaveMissing) {
  const std::vector<FoundSlave> none;
  const NetworkMatch m = match(none);
  EXPECT_TRUE(m.fatal);
  EXPECT_EQ(m.count(DifferenceKind::missing), kMaxSlaves);
  EXPECT_EQ(m.operated, 0u);
}

}  // namespace
}  // namespace rescue::ecat
