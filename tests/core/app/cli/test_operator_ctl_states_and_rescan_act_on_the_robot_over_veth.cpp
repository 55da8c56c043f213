// Issue 36 "Done means": `ctl rescan` and `ctl states` over veth, the path of the robot (the master on
// a raw socket, the segment served by `rescue-motion sim --iface` in another network namespace), not
// the in-process simulator. rescan finds the 23 devices as planned; l_hand, switched off and on again
// through the simulator's fault console, is out of service once the master recovered it (its joint
// stays recorded lost until cleared): `states l_hand PREOP` parks it there, `states l_hand OP` hands it
// back, while a slave whose joint is in service (l_elbow) is refused and nothing is written. Text and
// --json. Skipped where network namespaces cannot be made (tests/support/netns_veth.hpp).
#include <gtest/gtest.h>

#include "tests/support/ctl_over_veth.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using CtlOverVeth = rescue::testing::CtlOverVeth;

TEST_F(CtlOverVeth, RescanAndStatesActOnTheRobotThroughTheRawSocket) {
  start();
  if (HasFatalFailure()) return;

  const Answer rescan = ctl({"rescan"});
  EXPECT_EQ(rescan.status, 0) << rescan.out;
  EXPECT_TRUE(has(rescan.out, "23 devices on the wire, 23 identified; no difference from the plan\n")) << rescan.out;
  const Answer rescan_json = ctl({"--json", "rescan"});
  EXPECT_EQ(rescan_json.status, 0) << rescan_json.out;
  EXPECT_EQ(testing::json_field(rescan_json.out, "counted"), "23") << rescan_json.out;

  ASSERT_TRUE(sim_.write_input("power-off l_hand\n"));
  ASSERT_TRUE(run_.wait_for_output("link lost: l_hand", kTimeoutMs)) << run_.output();
  ASSERT_TRUE(sim_.write_input("power-on l_hand\n"));
  ASSERT_TRUE(run_.wait_for_output("link recovered: l_hand", kTimeoutMs)) << run_.output();

  const Answer in_service = ctl({"states", "l_elbow", "PREOP"});
  EXPECT_EQ(in_service.status, 1) << in_service.out;
  EXPECT_TRUE(has(in_service.out, "refused: joints of these slaves are in service")) << in_service.out;

  const Answer preop = ctl({"states", "l_hand", "PREOP"});
  ASSERT_EQ(preop.status, 0) << preop.out << run_.output();
  EXPECT_TRUE(has(preop.out, "l_hand")) << preop.out;
  EXPECT_TRUE(has(preop.out, "PREOP  reached (AL status 0x0002: PREOP)")) << preop.out;
  const Answer op = ctl({"--json", "states", "l_hand", "OP"});
  ASSERT_EQ(op.status, 0) << op.out << run_.output();
  EXPECT_EQ(testing::json_field(op.out, "status"), "ok") << op.out;
  EXPECT_TRUE(has(op.out, R"("outcome":"reached","al_status":"0x0008","al_state":"OP")")) << op.out;

  stop();
}

}  // namespace
}  // namespace rescue::app
