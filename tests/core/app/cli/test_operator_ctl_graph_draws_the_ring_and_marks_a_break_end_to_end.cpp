// `ctl graph` on the ring (issue 34, docs/redundancy.md "The ring in ctl graph"): against a real
// `rescue-motion run --ring-nic sim --scenario link-cut` (the in-process robot's ring configuration,
// both master ports; the cable into l_elbow cut 1 s after OP), the graph draws the ring's line (each
// slave's cable that of the line), the ring-return cable back to the master's second port, and the
// ring's state as the master judges it: closed before the cut; after it open between l_shoulder_yaw
// and l_elbow, that cable marked broken, one break counted, every slave still in OP. Text,
// --format dot (parsed by Graphviz's `dot`) and --json (parsed).
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

TEST(OperatorCtlGraphOnTheRing, DrawsTheRingAndMarksTheBreakWhereTheMasterPlacesIt) {
  OperatorRun run("60", "link-cut", {"--nic", "sim", "--ring-nic", "sim"});
  ASSERT_EQ(run.keygen.status, 0) << run.keygen.out;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const auto q = [&](const std::string& json, const std::string& expr) { return testing::json_query(run.dir.path, json, expr); };
  const std::string by_name = "{s['name']: s for s in d['slaves']}";

  const CommandResult before = run.ctl({"--json", "graph"});
  ASSERT_EQ(before.status, 0) << before.out;
  if (before.out.find("\"state\":\"open\"") == std::string::npos) {  // the cut may already have come on a slow host
    EXPECT_EQ(q(before.out, "d['ring']['state']"), R"("closed")") << before.out;
    EXPECT_EQ(q(before.out, "d['ring']['broken_cables']"), "[]") << before.out;
  }
  // The line: r_hand's port 1 to l_leg, neck_tilt's port 1 to l_shoulder_pitch; l_hand's port 1 back.
  EXPECT_EQ(q(before.out, "[((" + by_name + ")[n]['upstream'], (" + by_name + ")[n]['upstream_port']) for n in ('l_leg', 'l_shoulder_pitch')]"),
            R"([["r_hand", 1], ["neck_tilt", 1]])")
      << before.out;
  EXPECT_EQ(q(before.out, "(d['ring']['return_from'], d['ring']['return_port'])"), R"(["l_hand", 1])") << before.out;

  CommandResult after;
  for (int i = 0; i < 100; ++i) {
    after = run.ctl({"--json", "graph"});
    if (after.out.find("\"state\":\"open\"") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(after.status, 0) << after.out;
  EXPECT_EQ(q(after.out, "(d['ring']['state'], d['ring']['before'], d['ring']['after'], d['ring']['broken_cables'])"),
            R"(["open", "l_shoulder_yaw", "l_elbow", ["l_elbow"]])")
      << after.out;
  EXPECT_EQ(q(after.out, "(d['ring']['breaks'], d['ring']['repairs'])"), "[1, 0]") << after.out;
  EXPECT_EQ(q(after.out, "sorted(set((s['al_state'], s['service']) for s in d['slaves']))"), R"([["OP", "in exchange"]])")
      << "a single cut on the ring loses no slave: " << after.out;

  const CommandResult text = run.ctl({"graph"});
  ASSERT_EQ(text.status, 0) << text.out;
  EXPECT_NE(text.out.find("r_hand [OP] -> l_leg [OP]"), std::string::npos) << "one line through every slave: " << text.out;
  EXPECT_NE(text.out.find("l_shoulder_yaw [OP] -X- l_elbow [OP]"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("  l_shoulder_yaw:1 -> l_elbow: l_elbow,l_wrist_yaw,l_wrist_pitch,l_hand (broken)\n"), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("ring return: l_hand port 1 -> master ring port\n"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("ring: open between l_shoulder_yaw (position 18) and l_elbow (position 19); breaks 1, repairs 0"),
            std::string::npos)
      << text.out;

  const CommandResult dot = run.ctl({"graph", "--format", "dot"});
  ASSERT_EQ(dot.status, 0) << dot.out;
  EXPECT_NE(dot.out.find("s18 -> s19 [taillabel=\"1\", headlabel=\"0\", color=red, style=dashed, label=\"break\"]"),
            std::string::npos)
      << dot.out;
  EXPECT_NE(dot.out.find("s22 -> master [taillabel=\"1\", headlabel=\"ring\", style=bold]"), std::string::npos) << dot.out;
  const std::string file = run.dir.path + "/ring.dot";
  std::ofstream(file) << dot.out;
  ASSERT_EQ(std::system("command -v dot >/dev/null 2>&1"), 0) << "dot missing: bash toolchain/setup.sh installs graphviz";
  EXPECT_EQ(std::system(("dot -Tsvg '" + file + "' -o '" + file + ".svg'").c_str()), 0) << "Graphviz parses it";
  (void)run.stop();  // link-cut's verdict (joints lost) is the tree's; on the ring none is lost
  // The run's summary carries the ring's figures from the handler's process (the tasks run as processes).
  const std::string summary = run.output();
  EXPECT_NE(summary.find("ring_state: open (breaks 1, repairs 0)"), std::string::npos) << summary;
  EXPECT_NE(summary.find("ring_repeats: 0 (exchanges sent again"), std::string::npos) << summary;
}

}  // namespace
}  // namespace rescue::app
