// Issue 36 "Done means": `ctl sdos` and `ctl pdos` over veth, the path of the robot (the master on a
// raw socket, the segment served by `rescue-motion sim --iface` in another network namespace),
// not the in-process simulator: ctl in the master's namespace lists r_hand's dictionary (31 objects,
// 0x1018 a RECORD) and reads its PDOs back the same as configured, and a junction is refused by
// sdos (no mailbox) and said by pdos to map none; text and --json. Skipped where network namespaces cannot be made
// (CI must make them: tests/support/netns_veth.hpp).
#include <gtest/gtest.h>

#include "tests/support/ctl_over_veth.hpp"
#include "tests/support/json_query.hpp"

namespace rescue::app {
namespace {

using CtlOverVeth = rescue::testing::CtlOverVeth;

TEST_F(CtlOverVeth, SdosAndPdosReadADriveThroughTheRawSocket) {
  start();
  if (HasFatalFailure()) return;

  const Answer sdos = ctl({"sdos", "r_hand"});
  EXPECT_EQ(sdos.status, 0) << sdos.out;
  EXPECT_TRUE(has(sdos.out, ": 31 objects, as the slave describes them (CoE SDO Information)\n")) << sdos.out;
  EXPECT_TRUE(has(sdos.out, "SDO 0x1018, RECORD, max subindex 4, \"Identity\"\n")) << sdos.out;
  const Answer sdos_json = ctl({"--json", "sdos", "r_hand"});
  EXPECT_EQ(sdos_json.status, 0) << sdos_json.out;
  EXPECT_EQ(testing::json_query(dir_.path, sdos_json.out, "[d['ok'], d['slave'], len(d['objects'])]"), R"([true, "r_hand", 31])")
      << sdos_json.out;
  const Answer junction = ctl({"sdos", "junction_a"});
  EXPECT_EQ(junction.status, 1) << junction.out;
  EXPECT_TRUE(has(junction.out, "refused: no mailbox")) << junction.out;

  const Answer pdos = ctl({"pdos", "r_hand"});
  EXPECT_EQ(pdos.status, 0) << pdos.out;
  EXPECT_TRUE(has(pdos.out, "[same]")) << pdos.out;
  EXPECT_FALSE(has(pdos.out, "differs")) << pdos.out;
  const Answer pdos_json = ctl({"--json", "pdos", "r_hand"});
  EXPECT_EQ(pdos_json.status, 0) << pdos_json.out;
  EXPECT_EQ(testing::json_query(dir_.path, pdos_json.out, "[d['ok'], d['joint'], d['read_back_same']]"), R"([true, "r_hand", true])")
      << pdos_json.out;
  const Answer none = ctl({"pdos", "junction_a"});
  EXPECT_EQ(none.status, 0) << none.out;
  EXPECT_TRUE(has(none.out, "it maps no PDO")) << none.out;

  stop();
}

}  // namespace
}  // namespace rescue::app
