// Issue 36 item 2, `ctl sdos SLAVE [--values]` (docs/operator.md, IgH's `ethercat sdos`, SOEM's
// `slaveinfo -sdo`): a drive's object dictionary read through CoE SDO Information, request by
// request through the EtherCAT handler's mailbox, against the simulated robot: every object the
// drive serves (0x1000 ... 0x6502, ascending) with its object code, highest subindex and name, each
// entry with its type, bit length, access and name, and with --values its value (the identity's
// vendor id as a number, the device name as text); the same by the drive's position and in JSON. A
// junction (no mailbox) and a lost slave (the link-cut scenario cuts l_elbow's cable) are refused
// with the reason (exit 1); a bad SLAVE is a usage error (2), no robot is unreachable (3).
#include <gtest/gtest.h>

#include <string>

#include "core/robot/robot.hpp"
#include "drivers/joint/device_identity.hpp"
#include "tests/support/json_query.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::json_query;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(OperatorCtlSdos, ListsADrivesDictionaryWithItsValuesAndRefusesJunctionsAndLostSlaves) {
  OperatorRun run("60", "link-cut");
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  // r_hand is on the right arm: the link-cut scenario cuts the left arm's cable.
  const CommandResult text = run.ctl({"sdos", "r_hand"});
  ASSERT_EQ(text.status, 0) << text.out;
  EXPECT_TRUE(has(text.out, "r_hand (position ")) << text.out;
  EXPECT_TRUE(has(text.out, ": 31 objects, as the slave describes them (CoE SDO Information)\n")) << text.out;
  EXPECT_EQ(count(text.out, "\nSDO 0x"), 31U) << text.out;
  EXPECT_LT(text.out.find("SDO 0x1000, VAR"), text.out.find("SDO 0x6502, ")) << "ascending";
  EXPECT_TRUE(has(text.out, "SDO 0x1018, RECORD, max subindex 4, \"Identity\"\n")) << text.out;
  EXPECT_TRUE(has(text.out, "  0x1018:01, r-r-r-, UNSIGNED32, 32 bit, \"Vendor ID\"\n")) << text.out;
  EXPECT_TRUE(has(text.out, "  0x6041:00, r-r-r-, UNSIGNED16, 16 bit, \"Statusword\"\n")) << text.out;
  EXPECT_TRUE(has(text.out, "  0x6040:00, rwrwrw, UNSIGNED16, 16 bit, \"Controlword\"\n")) << text.out;
  EXPECT_TRUE(has(text.out, "  0x1C12:01, rwr-r-, UNSIGNED16, 16 bit, \"RxPDO assigned\"\n")) << text.out;
  EXPECT_FALSE(has(text.out, " = ")) << "no values without --values";

  const std::string position = std::to_string(slave_position_of_joint(joint_index_by_name("r_hand")));
  const CommandResult values = run.ctl({"sdos", position, "--values"});
  ASSERT_EQ(values.status, 0) << values.out;
  EXPECT_TRUE(has(values.out, "  0x1018:01, r-r-r-, UNSIGNED32, 32 bit, \"Vendor ID\" = 0x00000A5C 2652\n")) << values.out;
  EXPECT_TRUE(has(values.out, "\"Manufacturer device name\" = \"" + std::string(drivers::kJointDriveIdentity.name) + "\"\n"))
      << values.out;
  EXPECT_EQ(count(values.out, "\nSDO 0x"), 31U) << values.out;

  const CommandResult json = run.ctl({"--json", "sdos", "r_hand", "--values"});
  ASSERT_EQ(json.status, 0) << json.out;
  EXPECT_EQ(json_query(run.dir.path, json.out, "[d['ok'], d['slave'], d['joint'], d['values'], len(d['objects'])]"),
            R"([true, "r_hand", "r_hand", true, 31])")
      << json.out;
  EXPECT_EQ(json_query(run.dir.path, json.out,
                       "[(o['object_code'], o['max_subindex'], o['name'], len(o['entries']), o['entries'][1]['value']['number'])"
                       " for o in d['objects'] if o['index'] == '0x1018']"),
            R"([["RECORD", 4, "Identity", 5, 2652]])")
      << json.out;

  // A junction has no mailbox: refused with the reason, by name and by position alike.
  const CommandResult junction = run.ctl({"sdos", "junction_a"});
  EXPECT_EQ(junction.status, 1) << junction.out;
  EXPECT_TRUE(has(junction.out, "sdos: junction_a (position 0): the object list: refused: no mailbox: the slave has no CoE mailbox"))
      << junction.out;
  const CommandResult junction_json = run.ctl({"--json", "sdos", "0"});
  EXPECT_EQ(junction_json.status, 1) << junction_json.out;
  EXPECT_EQ(json_query(run.dir.path, junction_json.out, "[d['ok'], d['slave'], d['status']]"),
            R"([false, "junction_a", "no mailbox"])")
      << junction_json.out;

  EXPECT_EQ(run.ctl({"sdos", "tail"}).status, 2);
  EXPECT_EQ(run.ctl({"sdos"}).status, 2);
  EXPECT_EQ(run.ctl({"sdos", "r_hand", "extra"}).status, 2);
  EXPECT_EQ(run.ctl({"upload", "r_hand", "0x1000:00", "--values"}).status, 2) << "--values goes with sdos";
  EXPECT_EQ(testing::run_program({"ctl", "--key", run.key, "--port", std::to_string(testing::free_udp_port()), "--timeout",
                                  "0.2", "sdos", "r_hand"})
                .status,
            3);

  ASSERT_TRUE(run.wait_for("reconfiguration step 5")) << run.output();
  const CommandResult lost = run.ctl({"sdos", "l_elbow"});
  EXPECT_EQ(lost.status, 1) << lost.out;
  EXPECT_TRUE(has(lost.out, "refused: unreachable: the joint is lost or out of the exchange")) << lost.out;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
