// The records of the shared segment a task refuses as damaged (docs/shared-memory.md "Records: what
// each reader checks") reach the run's summary (core/app/runtime/segment_records_report.hpp): on the
// simulated robot a damaged demand and a damaged SDO request are the EtherCAT handler's count, which
// its loop publishes into its health slot (a restarted task process adds its own count to its
// predecessors'), and the summary prints one `segment_records_refused_TASK` line per task (n/a for
// the socket handler of a run without the operator port), the supervisor's damaged heartbeats and
// the total.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "core/app/links/task_links.hpp"
#include "core/app/runtime/segment_records_report.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_firmware_rig.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::app {
namespace {

std::string printed(const RunControl& run, std::uint64_t supervisor_beats, bool operator_port) {
  std::FILE* f = std::tmpfile();
  if (f == nullptr) return {};
  print_segment_records_refused(f, run, supervisor_beats, operator_port);
  std::rewind(f);
  std::string text;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, f) != nullptr) text += buffer;
  (void)std::fclose(f);
  return text;
}

TEST(SegmentRecordsReport, TheHandlersRefusalsAreCountedPublishedAndPrinted) {
  testing::TempStateDir dir;
  SimulatedFirmware fw(dir.path);
  ASSERT_TRUE(fw.start_enabled());
  EXPECT_EQ(damaged_records_of(*fw.handler), 0U);
  RobotDemand whole{};
  ASSERT_TRUE(fw.links->demand.try_read(whole));
  RobotDemand bad = whole;
  bad[0].mode = 3;  // a mode the joint manager never writes
  fw.links->demand.write(bad);
  fw.rig->clock.sleep_until(fw.rig->bus.next_wakeup());
  (void)fw.handler->cycle();  // one handler cycle alone: the joint manager's next demand is whole
  fw.links->demand.write(whole);
  SdoLinkRequest request;
  request.sdo.target = static_cast<protocol::SdoTarget>(9);
  ASSERT_TRUE(fw.links->sdo_requests.try_push(request));
  for (int i = 0; i < 5; ++i) (void)fw.period();
  EXPECT_EQ(damaged_records_of(*fw.handler), 2U);

  const std::unique_ptr<RunControl> run = std::make_unique<RunControl>();
  TaskHealth& slot = run->health[static_cast<std::size_t>(StatTask::ethercat_handler)];
  std::uint64_t published = 0;
  publish_damaged_records(slot, damaged_records_of(*fw.handler), published);
  publish_damaged_records(slot, damaged_records_of(*fw.handler), published);  // nothing new: nothing added
  EXPECT_EQ(slot.damaged_records.load(), 2U);
  std::uint64_t restarted = 0;  // a restarted process counts from 0 and adds its own
  publish_damaged_records(slot, 3, restarted);
  EXPECT_EQ(slot.damaged_records.load(), 5U);
  run->health[static_cast<std::size_t>(StatTask::rc_teleop)].damaged_records.store(1);

  run->health[static_cast<std::size_t>(StatTask::socket_handler)].damaged_records.store(2);
  const std::string text = printed(*run, 4, true);
  EXPECT_NE(text.find("segment_records_refused_ethercat_handler: 5\n"), std::string::npos) << text;
  EXPECT_NE(text.find("segment_records_refused_joint_manager: 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("segment_records_refused_socket_handler: 2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("segment_records_refused_rc_teleop: 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("segment_records_refused_supervisor: 4\n"), std::string::npos) << text;
  EXPECT_NE(text.find("segment_records_refused: 12\n"), std::string::npos) << text;
  // A run without the operator port has no socket handler: its line does not apply.
  const std::string without = printed(*run, 4, false);
  EXPECT_NE(without.find("segment_records_refused_socket_handler: n/a\n"), std::string::npos) << without;
  EXPECT_NE(without.find("segment_records_refused: 10\n"), std::string::npos) << without;
}

TEST(SegmentRecordsReport, EachTaskCountsWhatItsReadersRefused) {
  RcTaskCounters rc;
  rc.damaged_inputs = 7;
  EXPECT_EQ(damaged_records_of(rc), 7U);
  TaskHealth slot{};
  std::uint64_t published = 0;
  publish_damaged_records(slot, 0x1'0000'0005ULL, published);  // beyond the slot's 32 bits: saturated
  EXPECT_EQ(slot.damaged_records.load(), 0xFFFFFFFFU);
}

}  // namespace
}  // namespace rescue::app
