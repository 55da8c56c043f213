// Issue 36 item 3, `ctl reg_read SLAVE ADDR [LEN]` against a running robot (docs/operator.md "ESC
// registers"): the read goes through the operator protocol to the EtherCAT handler, whose master
// sends one FPRD in its cyclic frames, and comes back a period or more later: a drive's AL status
// (0x0130) reads OP (0x08), a junction's ESC type register (0x0000) reads as the simulated ESC
// holds it, --json carries the bytes as hex with the working counter; a slave that is lost (the
// link-cut scenario cuts l_elbow's cable) is refused with the reason (exit 1), its neighbours before
// the cut still read; a length past 64, a range past 0xFFFF, an address that is not a number and a
// slave that does not exist are usage errors (exit 2), nothing sent.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::json_field;
using testing::OperatorRun;

TEST(OperatorCtlRegRead, ReadsAnEscRegisterThroughTheCyclicFrameAndRefusesALostSlave) {
  OperatorRun run("30", "link-cut");
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult al = run.ctl({"reg_read", "l_elbow", "0x0130", "2"});
  ASSERT_EQ(al.status, 0) << al.out;
  EXPECT_EQ(al.out, "0x0130: 08 00\n") << "AL status OP, no error flag";
  const CommandResult json = testing::run_program(
      {"ctl", "--key", run.key, "--port", std::to_string(run.control_port), "--json", "reg_read", "0", "0x0000", "1"}, false);
  ASSERT_EQ(json.status, 0) << json.out;
  EXPECT_EQ(json_field(json.out, "slave"), "junction_a");
  EXPECT_EQ(json_field(json.out, "address"), "0x0000");
  EXPECT_EQ(json_field(json.out, "wkc"), "1");
  EXPECT_EQ(json_field(json.out, "bytes").size(), 2U) << json.out;
  const CommandResult long_read = run.ctl({"reg_read", "l_elbow", "0x0000", "64"});
  EXPECT_EQ(long_read.status, 0) << long_read.out;
  EXPECT_NE(long_read.out.find("0x0030:"), std::string::npos) << "four lines of 16\n" << long_read.out;

  EXPECT_EQ(run.ctl({"reg_read", "l_elbow", "0x0130", "65"}).status, 2);
  EXPECT_EQ(run.ctl({"reg_read", "l_elbow", "0xFFFF", "2"}).status, 2);
  EXPECT_EQ(run.ctl({"reg_read", "l_elbow", "AL"}).status, 2);
  EXPECT_EQ(run.ctl({"reg_read", "23", "0x0130"}).status, 2);
  EXPECT_EQ(run.ctl({"reg_read", "l_elbow"}).status, 2);

  ASSERT_TRUE(run.wait_for("reconfiguration step 5")) << run.output();
  const CommandResult lost = testing::run_program(
      {"ctl", "--key", run.key, "--port", std::to_string(run.control_port), "--json", "reg_read", "l_elbow", "0x0130", "2"},
      false);
  EXPECT_EQ(lost.status, 1) << lost.out;
  EXPECT_EQ(json_field(lost.out, "status"), "lost") << lost.out;
  EXPECT_NE(lost.out.find("nothing was sent"), std::string::npos) << lost.out;
  const CommandResult before_cut = run.ctl({"reg_read", "junction_a", "0x0130", "2"});
  EXPECT_EQ(before_cut.status, 0) << before_cut.out;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
