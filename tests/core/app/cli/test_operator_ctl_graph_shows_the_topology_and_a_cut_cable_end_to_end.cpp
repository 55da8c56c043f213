// Issue 24, `ctl graph` (docs/operator.md), like IgH's `ethercat graph`: against a real `rescue-motion
// run --scenario link-cut` (the cable into l_elbow cut 1 s after OP), the topology as the robot sees
// it: each slave's upstream slave and port (the junctions' ports, the chains), the joints behind
// every cable, and each slave's state now: before the cut all in OP, after it l_elbow and the slaves
// behind it lost, the rest in OP. Text, --format dot (its structure, and parsed by Graphviz's `dot`)
// and --json (parsed).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "tests/support/json_query.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(OperatorCtlGraph, ShowsTheTopologyTheJointsBehindEachCableAndACut) {
  OperatorRun run("60", "link-cut");
  ASSERT_EQ(run.keygen.status, 0) << run.keygen.out;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult before = run.ctl({"--json", "graph"});
  ASSERT_EQ(before.status, 0) << before.out;
  const auto q = [&](const std::string& json, const std::string& expr) { return testing::json_query(run.dir.path, json, expr); };
  const std::string by_name = "{s['name']: s for s in d['slaves']}";
  EXPECT_EQ(q(before.out, "len(d['slaves'])"), "23") << before.out;
  // The tree: junction_a on the master, junction_b on its port 3, the left arm on its port 2.
  EXPECT_EQ(q(before.out, "[(s['upstream'], s['upstream_port'], s['kind']) for s in d['slaves'] if s['name'] in "
                          "('junction_a', 'junction_b', 'l_shoulder_pitch', 'l_elbow')]"),
            R"([["master", 0, "junction"], ["junction_a", 3, "junction"], ["junction_a", 2, "joint_drive"], ["l_shoulder_yaw", 1, "joint_drive"]])")
      << before.out;
  EXPECT_EQ(q(before.out, "(" + by_name + ")['l_elbow']['joints_behind']"), R"(["l_elbow", "l_wrist_yaw", "l_wrist_pitch", "l_hand"])")
      << before.out;
  EXPECT_EQ(q(before.out, "len((" + by_name + ")['junction_a']['joints_behind'])"), "21") << before.out;
  EXPECT_EQ(q(before.out, "sorted(set((s['al_state'], s['service']) for s in d['slaves']))"), R"([["OP", "in exchange"]])")
      << before.out;

  const CommandResult dot = run.ctl({"graph", "--format", "dot"});
  ASSERT_EQ(dot.status, 0) << dot.out;
  EXPECT_EQ(dot.out.rfind("digraph robot {\n", 0), 0U) << dot.out;
  EXPECT_EQ(dot.out.substr(dot.out.size() - 2), "}\n") << dot.out;
  EXPECT_EQ(count_of(dot.out, " -> "), 23U) << "one edge per cable: " << dot.out;
  EXPECT_EQ(count_of(dot.out, "[label="), 24U) << "the master and 23 slaves: " << dot.out;
  EXPECT_NE(dot.out.find("s18 -> s19 [taillabel=\"1\""), std::string::npos) << "l_shoulder_yaw port 1 to l_elbow: " << dot.out;
  // Graphviz (Debian graphviz, in toolchain/setup.sh's list) parses it.
  const std::string file = run.dir.path + "/graph.dot";
  std::ofstream(file) << dot.out;
  ASSERT_EQ(std::system("command -v dot >/dev/null 2>&1"), 0) << "dot missing: bash toolchain/setup.sh installs graphviz";
  EXPECT_EQ(std::system(("dot -Tsvg '" + file + "' -o '" + file + ".svg'").c_str()), 0) << "Graphviz parses it";

  // After the cut: l_elbow and the slaves behind it lost, everything else in OP.
  ASSERT_TRUE(run.wait_for("link lost")) << run.output();
  CommandResult after;
  for (int i = 0; i < 100; ++i) {
    after = run.ctl({"--json", "graph"});
    if (after.out.find("\"service\":\"lost\"") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(after.status, 0) << after.out;
  EXPECT_EQ(q(after.out, "[s['name'] for s in d['slaves'] if s['service'] == 'lost']"),
            R"(["l_elbow", "l_wrist_yaw", "l_wrist_pitch", "l_hand"])")
      << after.out;
  EXPECT_EQ(q(after.out, "sorted(set(s['al_state'] for s in d['slaves'] if s['service'] != 'lost'))"), R"(["OP"])") << after.out;
  const CommandResult text = run.ctl({"graph"});
  ASSERT_EQ(text.status, 0) << text.out;
  EXPECT_NE(text.out.find("junction_a port 2 -> l_shoulder_pitch [OP] -> l_shoulder_roll [OP] -> l_shoulder_yaw [OP] -> l_elbow [lost"),
            std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("  l_shoulder_yaw:1 -> l_elbow: l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand\n"), std::string::npos) << text.out;
  EXPECT_NE(run.ctl({"graph", "--format", "dot"}).out.find("color=red"), std::string::npos) << "lost slaves drawn red";
  EXPECT_EQ(run.ctl({"graph", "--format", "svg"}).status, 2);
  EXPECT_EQ(run.ctl({"--json", "graph", "--format", "dot"}).status, 2);
  (void)run.stop();  // link-cut's own verdict is test_run_command_link_cut_scenario_end_to_end's
}

}  // namespace
}  // namespace rescue::app
