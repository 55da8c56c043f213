// Issue 36 item 1, `ctl pdos [SLAVE]` (docs/operator.md, like IgH's `ethercat pdos`): the sync
// managers, the PDO assignment and the mapping the master configures (this build's tables), and with
// SLAVE the same objects read back from that drive by SDO, against the simulated robot: every entry
// of l_elbow's and r_hand's drives reads back the same as configured, l_elbow by its position too;
// a junction maps none; an unknown name is a usage error; no robot is unreachable.
#include <gtest/gtest.h>

#include <string>

#include "core/robot/robot.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "tests/support/json_query.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(OperatorCtlPdos, ShowsTheConfiguredMappingAndReadsEachDrivesBack) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult plan = run.ctl({"pdos"});
  EXPECT_EQ(plan.status, 0) << plan.out;
  EXPECT_TRUE(has(plan.out, "SM2 outputs: 0x1C12 assigns PDO 0x1600, 13 bytes\n")) << plan.out;
  EXPECT_TRUE(has(plan.out, "SM3 inputs: 0x1C13 assigns PDO 0x1A00, 15 bytes\n")) << plan.out;
  EXPECT_TRUE(has(plan.out, "  0x607A:00 32 bit  offset  3  Target position\n")) << plan.out;
  EXPECT_FALSE(has(plan.out, "[same]")) << "nothing read back without JOINT: " << plan.out;

  const CommandResult text = run.ctl({"pdos", "l_elbow"});
  EXPECT_EQ(text.status, 0) << text.out;
  const std::size_t entries = drivers::kJointRxMapping.size() + drivers::kJointTxMapping.size();
  std::size_t same = 0;
  for (std::size_t at = text.out.find("[same]"); at != std::string::npos; at = text.out.find("[same]", at + 1)) ++same;
  EXPECT_EQ(same, entries + 2) << "every entry and both assignments: " << text.out;
  EXPECT_FALSE(has(text.out, "differs")) << text.out;

  const CommandResult json = run.ctl({"--json", "pdos", "r_hand"});
  EXPECT_EQ(json.status, 0) << json.out;
  EXPECT_EQ(testing::json_query(run.dir.path, json.out, "[d['ok'], d['joint'], d['read_back_same']]"), R"([true, "r_hand", true])")
      << json.out;
  EXPECT_EQ(testing::json_query(run.dir.path, json.out, "d['sync_managers'][1]['entries'][5]['read_back_word']"),
            "\"0x603F0010\"")
      << json.out;

  // SLAVE as for upload: a drive by its position reads back as by its joint; a junction maps none.
  const std::string elbow = std::to_string(slave_position_of_joint(joint_index_by_name("l_elbow")));
  const CommandResult by_position = run.ctl({"pdos", elbow});
  EXPECT_EQ(by_position.status, 0) << by_position.out;
  EXPECT_EQ(by_position.out, text.out);
  const CommandResult junction = run.ctl({"pdos", "junction_a"});
  EXPECT_EQ(junction.status, 0) << junction.out;
  EXPECT_TRUE(has(junction.out, "junction_a (position 0): a junction: it maps no PDO")) << junction.out;
  const CommandResult junction_json = run.ctl({"--json", "pdos", "0"});
  EXPECT_EQ(junction_json.status, 0) << junction_json.out;
  EXPECT_EQ(testing::json_query(run.dir.path, junction_json.out, "[d['ok'], d['slave'], d['joint'], d['sync_managers']]"),
            R"([true, "junction_a", null, []])")
      << junction_json.out;
  EXPECT_EQ(run.ctl({"pdos", "tail"}).status, 2);
  EXPECT_EQ(run.ctl({"pdos", "l_elbow", "extra"}).status, 2);
  EXPECT_EQ(testing::run_program({"ctl", "--key", run.key, "--port", std::to_string(testing::free_udp_port()), "--timeout",
                                  "0.2", "pdos", "l_elbow"})
                .status,
            3);
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
