// Link diagnostics on the simulated robot: damage injected on one cable (frames received with a
// broken FCS on one port) shows in that slave's and port's counters, read in the low-rate round
// robin of the cyclic frame, and raises one `port_errors` report naming the cable's two ends; the
// forwarded errors it causes further on never raise a warning, and a healthy network raises none.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

using testing::SimulatedRobotRig;

std::unique_ptr<SimulatedRobotRig> robot_in_op() { return testing::simulated_robot_in_op(); }

// Cycles `n` periods, collecting port_errors reports.
std::vector<LinkReport> run(SimulatedRobotRig& rig, int n) {
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  std::vector<LinkReport> warnings;
  LinkReport report;
  for (int i = 0; i < n; ++i) {
    (void)rig.cycle(refs, fb);
    while (rig.bus.master().pop_report(report)) {
      if (report.kind == LinkEventKind::port_errors) warnings.push_back(report);
    }
  }
  return warnings;
}

const char* slave_name(std::size_t position) { return kSlaves[position].name; }

TEST(MasterLinkDiagnostics, AHealthyNetworkRaisesNoWarning) {
  auto rig = robot_in_op();
  EXPECT_TRUE(run(*rig, 3000).empty());
  const LinkDiagnostics& d = rig->bus.master().diagnostics();
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    EXPECT_GE(d.counters(p).reads, 10u) << "every slave is read in the round robin: " << kSlaves[p].name;
    for (const PortCounters& port : d.counters(p).ports) EXPECT_EQ(port.invalid_frames + port.rx_errors, 0u);
  }
}

TEST(MasterLinkDiagnostics, DamageOnOneCableIsCountedAndWarnedNamingBothEnds) {
  auto rig = robot_in_op();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  const std::size_t shoulder_yaw = slave_position_of_joint(joint_index_by_name("l_shoulder_yaw"));
  ASSERT_EQ(drivers::kRobotNetworkPlan[elbow].upstream, shoulder_yaw);
  ASSERT_TRUE(rig->segment.corrupt_port(elbow, 0, 5).ok());
  const std::vector<LinkReport> warnings = run(*rig, 1000);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].slaves, slave_bit(elbow));
  EXPECT_EQ(warnings[0].found[0], 0u);             // port
  EXPECT_EQ(warnings[0].found[1], shoulder_yaw);   // the cable's other end
  EXPECT_EQ(warnings[0].found[2], 5u);             // errors so far
  const LinkDiagnostics& d = rig->bus.master().diagnostics();
  EXPECT_EQ(d.counters(elbow).ports[0].invalid_frames, 5u);
  EXPECT_EQ(d.counters(elbow + 1).ports[0].forwarded_errors, 5u) << "the next slave saw them forwarded";
  EXPECT_EQ(d.counters(shoulder_yaw).ports[0].invalid_frames, 0u);
  // The table names the slave and its counters (printed for the docs).
  char text[8192] = {};
  std::FILE* f = fmemopen(text, sizeof text - 1, "w");
  ASSERT_NE(f, nullptr);
  d.print_table(f, slave_bit(shoulder_yaw) | slave_bit(elbow) | slave_bit(elbow + 1), slave_name);
  std::fclose(f);
  EXPECT_NE(std::string(text).find("l_elbow"), std::string::npos);
  std::printf("%s", text);
}

TEST(MasterLinkDiagnostics, DamageSeenOnADownstreamPortNamesTheSameCable) {
  auto rig = robot_in_op();
  const std::size_t elbow = slave_position_of_joint(joint_index_by_name("l_elbow"));
  const std::size_t shoulder_yaw = slave_position_of_joint(joint_index_by_name("l_shoulder_yaw"));
  const unsigned port = drivers::kRobotNetworkPlan[elbow].upstream_port;
  ASSERT_TRUE(rig->segment.corrupt_port(shoulder_yaw, port, 4).ok());
  const std::vector<LinkReport> warnings = run(*rig, 1000);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].slaves, slave_bit(shoulder_yaw));
  EXPECT_EQ(warnings[0].found[0], port);
  EXPECT_EQ(warnings[0].found[1], elbow);
}

}  // namespace
}  // namespace rescue::ecat
