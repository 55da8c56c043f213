// Issue 36 item 3, `ctl states [SLAVES] STATE` against a running robot (docs/operator.md "AL states"):
// the power-cycle scenario power-cycles l_elbow's drive; the master's online recovery brings it back
// to OP while its joint stays out of service (recorded lost until a clear). Then its AL state is the
// operator's: PREOP is reached (ctl slaves -v shows it in PREOP) and it stays there, parked, its joint
// not clearable, until OP hands it back to the recovery (its AL status register reads OP again
// through ctl reg_read). A slave
// whose joints are in service is refused with them named (exit 1), also inside a list (all or
// nothing: l_elbow is not touched), and so is a junction carrying joints in service; a state that is
// not INIT/PREOP/SAFEOP/OP or a slave that does not exist is a usage error (exit 2), nothing sent.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::json_field;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// The line of `ctl slaves -v` for l_elbow (its AL state as the master last read it).
std::string elbow_line(OperatorRun& run) {
  const std::string out = run.ctl({"slaves", "-v"}).out;
  const std::size_t at = out.find("0x1013  l_elbow");
  return at == std::string::npos ? out : out.substr(at, out.find('\n', at) - at);
}

TEST(OperatorCtlStates, ParksAnOutOfServiceDriveAtPreOpAndRefusesSlavesInService) {
  OperatorRun run("60", "power-cycle");
  ASSERT_EQ(run.keygen.status, 0) << run.keygen.out;
  ASSERT_TRUE(run.wait_for("link recovered: l_elbow")) << run.output();

  const CommandResult in_service = run.ctl({"states", "l_wrist_yaw", "PREOP"});
  EXPECT_EQ(in_service.status, 1) << in_service.out;
  EXPECT_TRUE(has(in_service.out, "states: PREOP: refused: joints of these slaves are in service")) << in_service.out;
  EXPECT_TRUE(has(in_service.out, "joints in service: l_wrist_yaw\n")) << in_service.out;
  const CommandResult mixed = run.ctl({"states", "l_elbow,l_wrist_yaw", "PREOP"});
  EXPECT_EQ(mixed.status, 1) << mixed.out;
  EXPECT_EQ(run.ctl({"reg_read", "l_elbow", "0x0130", "2"}).out, "0x0130: 08 00\n") << "all or nothing";
  const CommandResult junction = run.ctl({"--json", "states", "junction_b", "INIT"});
  EXPECT_EQ(junction.status, 1) << junction.out;
  EXPECT_EQ(json_field(junction.out, "status"), "in service") << junction.out;
  EXPECT_TRUE(has(junction.out, R"("in_service":["r_shoulder_pitch",)")) << junction.out;

  const CommandResult preop = run.ctl({"states", "l_elbow", "preop"});
  ASSERT_EQ(preop.status, 0) << preop.out << run.output();
  EXPECT_EQ(preop.out, "l_elbow          PREOP  reached (AL status 0x0002: PREOP)\n");
  // Out of the exchange now (ctl reg_read refuses it), its AL state as the master read it.
  EXPECT_TRUE(has(elbow_line(run), " PREOP ")) << elbow_line(run);
  // Parked: half a second on, the online recovery has not taken it back to OP, and its joint
  // cannot be cleared (its slave is out of the exchange) until OP.
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_TRUE(has(elbow_line(run), " PREOP ")) << elbow_line(run);
  const CommandResult clear = run.ctl({"clear", "l_elbow"});
  EXPECT_EQ(clear.status, 1) << clear.out;
  EXPECT_TRUE(has(clear.out, "still unreachable")) << clear.out;

  const CommandResult op = run.ctl({"--json", "states", "19", "OP"});
  ASSERT_EQ(op.status, 0) << op.out << run.output();
  EXPECT_EQ(json_field(op.out, "status"), "ok") << op.out;
  EXPECT_TRUE(has(op.out, R"({"slave":"l_elbow","position":19,"outcome":"reached","al_status":"0x0008","al_state":"OP")"))
      << op.out;
  EXPECT_EQ(run.ctl({"reg_read", "l_elbow", "0x0130", "2"}).out, "0x0130: 08 00\n");

  EXPECT_EQ(run.ctl({"states", "l_elbow", "BOOT"}).status, 2);
  EXPECT_EQ(run.ctl({"states", "nosuch", "INIT"}).status, 2);
  EXPECT_EQ(run.ctl({"states", "l_elbow,", "INIT"}).status, 2);
  EXPECT_EQ(run.ctl({"states"}).status, 2);
  EXPECT_EQ(run.ctl({"states", "OP"}).status, 1) << "every slave: joints in service";
  // Stopped before the scenario's own end: its verdict (the exit status) is not this test's subject.
  (void)run.stop();
}

}  // namespace
}  // namespace rescue::app
