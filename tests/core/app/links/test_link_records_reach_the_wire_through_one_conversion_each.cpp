// The one conversion per record between the tasks' records (core/app/links/) and the operator
// protocol's messages (control_messages.hpp): every field of MasterStatus, TaskStat and a joint's
// published status and sample lands in its own field of the answer, and a record not published
// yet leaves its part of the answer at the protocol's defaults.
#include <gtest/gtest.h>

#include "core/app/links/control_messages.hpp"

namespace rescue::app {
namespace {

TEST(LinkRecordsToWire, MasterStatusFillsEveryMasterField) {
  MasterStatus s{};
  s.state = 8;
  s.cycles = 11;
  s.frames_sent = 12;
  s.frames_lost = 13;
  s.late_periods = 14;
  s.dc_deviation_ns = -15;
  s.dc_max_deviation_ns = 16;
  const protocol::MasterPayload p = master_payload_of(s);
  EXPECT_EQ(p.state, 8);
  EXPECT_EQ(p.cycles, 11U);
  EXPECT_EQ(p.frames_sent, 12U);
  EXPECT_EQ(p.frames_lost, 13U);
  EXPECT_EQ(p.late_periods, 14U);
  EXPECT_EQ(p.dc_deviation_ns, -15);
  EXPECT_EQ(p.dc_max_deviation_ns, 16);
  EXPECT_EQ(p.datagrams_accepted, 0U) << "the socket handler's own, added by it";
  EXPECT_FALSE(p.age.stale);
}

TEST(LinkRecordsToWire, TaskStatGivesTheKernelsViewBesideTheTaskTables) {
  TaskStat t{};
  t.name = {'e', 't', 'h', 'e', 'r', 'c', 'a', 't'};
  t.pid = 4242;
  t.cpu = 3;
  t.priority = 90;
  t.kernel_cpu = 1;
  t.kernel_priority = 80;
  t.kernel_policy = 1;
  t.periods = 1000;
  t.missed = 2;
  t.max_execution_ns = 35000;
  t.execution.p99 = 20000;
  t.latency.max = 7000;
  TaskHealth health{};
  health.tid.store(4250);
  health.restarts.store(70000);  // saturates on the wire
  health.started_ns.store(5'000'000'000);
  const protocol::TaskRecord r = task_record_of(t, &health, 7'500'000'000);
  EXPECT_EQ(r.tid, 4250) << "the task's own thread, not its process";
  EXPECT_EQ(r.restarts, 0xFFFF);
  EXPECT_EQ(r.uptime_ms, 2500U);
  EXPECT_EQ(task_record_of(t, nullptr, 7'500'000'000).uptime_ms, protocol::kUptimeUnknown) << "no health slot: not known";
  health.started_ns.store(0);
  EXPECT_EQ(task_record_of(t, &health, 7'500'000'000).uptime_ms, protocol::kUptimeUnknown) << "not started: not known";
  EXPECT_STREQ(r.name.data(), "ethercat");
  EXPECT_EQ(r.pid, 4242);
  EXPECT_EQ(r.cpu, 1) << "where the kernel ran it";
  EXPECT_EQ(r.priority, 80);
  EXPECT_EQ(r.policy, 1);
  EXPECT_EQ(r.table_cpu, 3) << "what the task table asked for";
  EXPECT_EQ(r.table_priority, 90);
  EXPECT_EQ(r.periods, 1000U);
  EXPECT_EQ(r.missed, 2U);
  EXPECT_EQ(r.max_execution_ns, 35000U);
  EXPECT_EQ(r.execution.p99, 20000U);
  EXPECT_EQ(r.latency.max, 7000U);
}

TEST(LinkRecordsToWire, AJointsStatusAndSampleMakeItsStatusRecord) {
  PublishedJointStatus status{};
  status.state = fsm::JointState::enabled;
  status.mode = ControlMode::cyclic_position;
  status.drive_enabled = true;
  status.lost = true;
  status.fault = FaultReason::position_limit;
  JointSample sample{};
  sample.reachable = true;
  sample.drive_fault = true;
  sample.position_rad = 0.5;
  sample.velocity_rad_s = -0.25;
  sample.torque_nm = 3.0;
  const protocol::JointStatusRecord r = joint_status_record_of(&status, &sample, 1);
  EXPECT_EQ(r.state, static_cast<std::uint8_t>(fsm::JointState::enabled));
  EXPECT_EQ(r.mode, static_cast<std::int8_t>(ControlMode::cyclic_position));
  EXPECT_EQ(r.fault, static_cast<std::uint8_t>(FaultReason::position_limit));
  EXPECT_EQ(r.flags, protocol::kFlagDriveEnabled | protocol::kFlagLost | protocol::kFlagReachable | protocol::kFlagDriveFault);
  EXPECT_DOUBLE_EQ(r.position_rad, 0.5);
  EXPECT_DOUBLE_EQ(r.velocity_rad_s, -0.25);
  EXPECT_DOUBLE_EQ(r.torque_nm, 3.0);
  EXPECT_EQ(r.owner, 1);

  const protocol::JointStatusRecord none = joint_status_record_of(nullptr, nullptr, protocol::kNoOwner);
  EXPECT_EQ(none.state, 0);
  EXPECT_EQ(none.flags, 0);
  EXPECT_DOUBLE_EQ(none.position_rad, 0.0);
  EXPECT_EQ(none.owner, protocol::kNoOwner);
}

}  // namespace
}  // namespace rescue::app
