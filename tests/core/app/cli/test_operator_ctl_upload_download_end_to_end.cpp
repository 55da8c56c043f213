// Issue 24, ctl upload / ctl download against a running robot (docs/operator.md "SDO"), every answer
// parsed from --json: the drive's firmware version (0x100A, a string longer than one mailbox:
// segmented upload) and its device name; a download of a writable object (0x6065 following error
// window, and the 0x2010 application label, segmented) read back with its new value; a download to
// the target position (0x607A, in the RxPDO) refused with that reason and exit status 1; an unknown
// object aborted with its SDO abort code by name; and the robot's late periods over windows of
// segmented SDO traffic (the transfers run one mailbox step per cyclic frame, never inside a wait:
// proved in virtual time by test_mailbox_client_runs_expedited_and_segmented_sdo_in_the_cyclic_frame).
// On the wall clock a late wake-up may be the host's own (a kernel without PREEMPT_RT, a hypervisor
// that stalls vCPUs, a handler the kernel refused SCHED_FIFO; it happens with `ctl status` traffic
// too, and one CI machine showed 2 late periods in each of three windows), and host jitter is never
// taken for a fault. So: with the handler at SCHED_FIFO on a PREEMPT_RT kernel, one of three windows
// must have no late period; with SCHED_FIFO on another kernel, the fewest late periods of a window
// must be fewer than the window's transfers, since a transfer that made the handler wait would make
// it late at least once per transfer, in every window; a handler the kernel refused SCHED_FIFO
// competes with every other program for the CPU (9 to 18 late periods a window under stress-ng),
// and nothing about its lateness is asserted. The windows' figures are printed every time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/app/bench/bench_header.hpp"
#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::json_field;
using testing::OperatorRun;

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(OperatorSdoVerbs, UploadDownloadAndRefusalsAgainstARunningRobot) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const CommandResult before = run.ctl({"--json", "master"});
  ASSERT_EQ(before.status, 0) << before.out;
  const std::string late_before = json_field(before.out, "late_periods");

  const CommandResult version = run.ctl({"--json", "upload", "l_elbow", "0x100A:00"});
  ASSERT_EQ(version.status, 0) << version.out;
  EXPECT_EQ(json_field(version.out, "ok"), "true") << version.out;
  EXPECT_EQ(json_field(version.out, "type"), "string") << version.out;
  EXPECT_EQ(json_field(version.out, "value"), drivers::kJointDriveFirmwareVersion) << version.out;
  EXPECT_EQ(json_field(version.out, "segmented"), "true") << version.out;
  const CommandResult version_text = run.ctl({"upload", "l_elbow", "0x100A:00"});
  EXPECT_EQ(version_text.out, std::string(drivers::kJointDriveFirmwareVersion) + "\n");

  const CommandResult name = run.ctl({"--json", "upload", "neck_pan", "0x1008:00"});
  ASSERT_EQ(name.status, 0) << name.out;
  EXPECT_EQ(json_field(name.out, "value"), "RM-JD402") << name.out;
  const CommandResult error_code = run.ctl({"--json", "upload", "l_elbow", "0x603F:00"});
  ASSERT_EQ(error_code.status, 0) << error_code.out;
  EXPECT_EQ(json_field(error_code.out, "value"), "0") << error_code.out;
  EXPECT_EQ(json_field(error_code.out, "hex"), "0x0000") << error_code.out;
  const CommandResult temperature = run.ctl({"upload", "l_elbow", "0x2002:00", "--type", "i16"});
  ASSERT_EQ(temperature.status, 0) << temperature.out;
  EXPECT_TRUE(has(temperature.out, "0x") && temperature.out.size() > 8) << temperature.out;

  const CommandResult written = run.ctl({"--json", "download", "l_elbow", "0x6065:00", "4321", "--type", "u32"});
  ASSERT_EQ(written.status, 0) << written.out;
  EXPECT_EQ(json_field(written.out, "ok"), "true") << written.out;
  const CommandResult read_back = run.ctl({"--json", "upload", "l_elbow", "0x6065:00"});
  EXPECT_EQ(json_field(read_back.out, "value"), "4321") << read_back.out;
  EXPECT_EQ(json_field(read_back.out, "hex"), "0x000010E1") << read_back.out;

  const std::string label = "l_elbow: drive replaced after the stairs trial, harness B7 re-crimped, encoder offset checked "
                            "on the jig; next service at 500 h";
  const CommandResult labelled = run.ctl({"download", "l_elbow", "0x2010:00", label});  // no --type: the object's
  ASSERT_EQ(labelled.status, 0) << labelled.out;
  const CommandResult label_back = run.ctl({"--json", "upload", "l_elbow", "0x2010:00"});
  EXPECT_EQ(json_field(label_back.out, "value"), label) << label_back.out;
  EXPECT_EQ(json_field(label_back.out, "segmented"), "true") << label_back.out;

  const CommandResult refused = run.ctl({"--json", "download", "l_elbow", "0x607A:00", "1000", "--type", "i32"});
  EXPECT_EQ(refused.status, 1) << refused.out;
  EXPECT_EQ(json_field(refused.out, "ok"), "false") << refused.out;
  EXPECT_EQ(json_field(refused.out, "status"), "mapped object") << refused.out;
  EXPECT_EQ(json_field(refused.out, "reason"), "0x607A:00 is in the RxPDO: the cyclic image writes it") << refused.out;
  const CommandResult refused_text = run.ctl({"download", "l_elbow", "0x607A:00", "1000", "--type", "i32"});
  EXPECT_EQ(refused_text.status, 1);
  EXPECT_TRUE(has(refused_text.out, "refused: mapped object: 0x607A:00 is in the RxPDO")) << refused_text.out;

  const CommandResult missing = run.ctl({"--json", "upload", "l_elbow", "0x5FFF:00"});
  EXPECT_EQ(missing.status, 1) << missing.out;
  EXPECT_EQ(json_field(missing.out, "status"), "aborted") << missing.out;
  EXPECT_EQ(json_field(missing.out, "abort_code"), "0x06020000") << missing.out;
  EXPECT_EQ(json_field(missing.out, "reason"), "object does not exist in the object dictionary") << missing.out;

  const CommandResult bad = run.ctl({"--json", "upload", "l_elbw", "0x1008:00"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_TRUE(has(bad.out, "'l_elbw' is not a slave")) << bad.out;

  EXPECT_FALSE(late_before.empty()) << before.out;
  constexpr std::uint64_t kTransfersPerWindow = 9;
  const bool fifo = run.handler_got_sched_fifo();
  const bool asserted_zero = fifo && kernel_is_preempt_rt();
  std::uint64_t fewest_late = UINT64_MAX;
  std::string windows;
  for (int window = 0; window < 3 && fewest_late != 0; ++window) {
    const std::string late_start = json_field(run.ctl({"--json", "master"}).out, "late_periods");
    for (std::uint64_t i = 0; i < kTransfersPerWindow / 3; ++i) {
      EXPECT_EQ(run.ctl({"upload", "l_elbow", "0x100A:00"}).status, 0);
      EXPECT_EQ(run.ctl({"download", "l_elbow", "0x2010:00", label, "--type", "string"}).status, 0);
      EXPECT_EQ(run.ctl({"upload", "l_elbow", "0x2010:00"}).status, 0);
    }
    const std::string late_end = json_field(run.ctl({"--json", "master"}).out, "late_periods");
    ASSERT_FALSE(late_start.empty() || late_end.empty()) << "ctl master gave no late_periods";
    const std::uint64_t late = std::stoull(late_end) - std::stoull(late_start);
    windows += " " + late_start + "->" + late_end;
    fewest_late = std::min(fewest_late, late);
  }
  std::printf("handler late periods in windows of %llu SDO transfers:%s (SCHED_FIFO %s, PREEMPT_RT kernel %s: %s)\n",
              static_cast<unsigned long long>(kTransfersPerWindow), windows.c_str(),
              fifo ? "applied" : "refused", kernel_is_preempt_rt() ? "yes" : "no",
              asserted_zero ? "one window without a late period asserted"
              : fifo        ? "fewer late periods than transfers asserted"
                            : "not real-time, not asserted");
  if (asserted_zero) {
    EXPECT_EQ(fewest_late, 0U) << "late periods rose in every window of SDO traffic:" << windows;
  } else if (fifo) {
    EXPECT_LT(fewest_late, kTransfersPerWindow) << "a late period per transfer in every window:" << windows;
  }
  EXPECT_EQ(run.stop(), 0) << run.output();
}

// Issue 36 item 4: SLAVE is a joint, a slave's name or its position (IgH's `-p`), so the junctions
// are addressed too: a drive by its position answers as by its joint; junction_a (no mailbox) is
// refused with that reason, exit 1; a position past the last slave is usage, exit 2, nothing sent.
TEST(OperatorSdoVerbs, UploadAndDownloadAddressASlaveByItsPositionAndTheJunctions) {
  OperatorRun run;
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  const std::string elbow = std::to_string(slave_position_of_joint(joint_index_by_name("l_elbow")));
  const CommandResult by_position = run.ctl({"--json", "upload", elbow, "0x1008:00"});
  ASSERT_EQ(by_position.status, 0) << by_position.out;
  EXPECT_EQ(json_field(by_position.out, "value"), "RM-JD402") << by_position.out;
  EXPECT_EQ(json_field(by_position.out, "slave"), "l_elbow") << by_position.out;
  EXPECT_EQ(json_field(by_position.out, "position"), elbow) << by_position.out;
  EXPECT_EQ(json_field(by_position.out, "joint"), "l_elbow") << by_position.out;
  EXPECT_EQ(run.ctl({"upload", elbow, "0x1008:00"}).out, "RM-JD402\n");

  const CommandResult written = run.ctl({"download", elbow, "0x6065:00", "1234"});  // size from the object
  EXPECT_EQ(written.status, 0) << written.out;
  EXPECT_EQ(written.out, "download: l_elbow 0x6065:00 written\n");
  EXPECT_EQ(json_field(run.ctl({"--json", "upload", "l_elbow", "0x6065:00"}).out, "value"), "1234");
  const CommandResult mapped = run.ctl({"download", elbow, "0x607A:00", "1000", "--type", "i32"});
  EXPECT_EQ(mapped.status, 1) << mapped.out;
  EXPECT_TRUE(has(mapped.out, "refused: mapped object")) << mapped.out;

  const CommandResult junction = run.ctl({"--json", "upload", "junction_a", "0x1018:01"});
  EXPECT_EQ(junction.status, 1) << junction.out;
  EXPECT_EQ(json_field(junction.out, "slave"), "junction_a") << junction.out;
  EXPECT_EQ(json_field(junction.out, "position"), "0") << junction.out;
  EXPECT_EQ(json_field(junction.out, "joint"), "null") << junction.out;
  EXPECT_EQ(json_field(junction.out, "status"), "no mailbox") << junction.out;
  const CommandResult junction_text = run.ctl({"upload", "1", "0x1018:01"});
  EXPECT_EQ(junction_text.status, 1);
  EXPECT_EQ(junction_text.out, "upload: junction_b 0x1018:01: refused: no mailbox: the slave has no CoE mailbox\n");

  const CommandResult past = run.ctl({"upload", "23", "0x1018:01"});
  EXPECT_EQ(past.status, 2);
  EXPECT_TRUE(has(past.out, "'23' is not a slave")) << past.out;
  EXPECT_EQ(run.stop(), 0) << run.output();
}

}  // namespace
}  // namespace rescue::app
