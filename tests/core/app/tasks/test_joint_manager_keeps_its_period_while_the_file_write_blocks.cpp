// Issue 21 item 2: the joint manager never waits for the disk. Its storage worker runs on a thread of
// its own over the firmware's queues (SpscQueue), with a storage whose save blocks for 2 s of the joint
// manager's time (2000 periods: it returns only when the test releases it). Meanwhile the joint
// manager, on virtual time, keeps completing its periods: the lost joints go to Error at once, a limit
// violation during the write takes its joint to Error, and the handler's answer waits for the write.
// Once the save returns, the file is durable and the answer goes out. No timing threshold: the proof is
// that every one of those periods completed while the worker was still inside save().
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

using fsm::JointInput;
using fsm::JointState;

const std::size_t kElbow = joint_index_by_name("l_elbow");
const JointMask kElbowCut = joints_lost_by_link_failure_at(kElbow);
const std::size_t kRightElbow = joint_index_by_name("r_elbow");
constexpr int kBlockedPeriods = 2000;  // 2 s of the joint manager's 1 ms periods

TEST(JointManagerDuringABlockedWrite, KeepsItsPeriodChecksLimitsAndAnswersOnceTheFileIsDurable) {
  testing::TempStateDir dir;
  ErrorJointsFileStorage files(dir.path.c_str());
  testing::BlockingDisk disk(files);
  testing::ThreadedStorageWorker storage(disk);  // the real worker on its own thread, not the rig's inline one
  testing::Rig rig(disk);
  JointManagerPorts ports = rig.ports();
  storage.wire(ports);
  JointManager manager(ports);
  (void)manager.restore(0);

  hal::VirtualClock clock;
  std::int64_t longest_step_ns = 0;
  auto period = [&] {
    clock.advance(hal::kNsPerMs);
    const auto begun = std::chrono::steady_clock::now();
    manager.step(clock.now());
    const auto took = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - begun).count();
    if (took > longest_step_ns) longest_step_ns = took;
  };
  rig.command(kAllJoints, JointInput::select_mode, ControlMode::cyclic_position);
  rig.command(kAllJoints, JointInput::set_reference);
  rig.command(kAllJoints, JointInput::enable);
  period();
  ASSERT_EQ(manager.statuses()[kRightElbow].state, JointState::enabled);

  // The link into l_elbow is cut: the handler reports it; the file's write goes to the worker.
  rig.samples.lose(kElbowCut);
  ASSERT_TRUE(rig.reports.try_send(LostJointsReport{kElbowCut, 1000, clock.now()}));
  period();
  while (!disk.in_save.load()) std::this_thread::yield();  // the worker is inside the write

  int periods_during_write = 0;
  for (int i = 0; i < kBlockedPeriods; ++i) {
    if (i == 500) rig.samples.robot[kRightElbow].velocity_rad_s = 2.0 * kJoints[kRightElbow].limits.velocity_max_rad_s;
    period();
    ++periods_during_write;
  }
  // Every one of those periods completed while the save had not returned.
  EXPECT_TRUE(disk.in_save.load());
  EXPECT_EQ(disk.saves_returned.load(), 0);
  EXPECT_EQ(periods_during_write, kBlockedPeriods);
  EXPECT_TRUE(manager.write_in_flight());
  EXPECT_TRUE(manager.file_dirty());
  // Safety did not wait for the disk: the lost joints are in Error, and so is the joint whose limit
  // was violated during the write.
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((kElbowCut & joint_bit(j)) != 0) {
      EXPECT_EQ(manager.statuses()[j].state, JointState::error) << kJoints[j].name;
    }
  }
  EXPECT_EQ(manager.statuses()[kRightElbow].state, JointState::error);
  EXPECT_EQ(manager.statuses()[kRightElbow].fault.reason, FaultReason::velocity_limit);
  EXPECT_EQ(manager.statuses()[joint_index_by_name("r_shoulder_pitch")].state, JointState::enabled);
  // Steps 3-4 wait for the durable write: no answer yet, no "wrote" line, nothing on disk.
  EXPECT_EQ(rig.notices.size(), 0u);
  EXPECT_TRUE(rig.log.of(JointEventKind::file_written).empty());
  EXPECT_FALSE(files.load().file_present);

  disk.release();
  for (int i = 0; i < 1'000'000 && manager.file_dirty(); ++i) {  // bounded; the worker answers within a poll
    period();
    std::this_thread::yield();
  }
  storage.stop();

  EXPECT_FALSE(manager.file_dirty());
  const ErrorJointsLoad load = files.load();
  ASSERT_TRUE(load.file_present);
  EXPECT_TRUE(load.decoded.status.ok());
  EXPECT_EQ(load.decoded.contents.joints(), kElbowCut);  // durable: read back from the disk
  JointManagerNotice answer;
  ASSERT_TRUE(rig.notices.try_receive(answer));
  EXPECT_EQ(answer.kind, NoticeKind::lost_joints_recorded);
  EXPECT_EQ(answer.joints, kElbowCut);
  EXPECT_EQ(answer.file_status, Errc::ok);
  EXPECT_EQ(manager.file_writes(), 1u);
  // For the record (not asserted: a loaded host stretches it), the longest period's wall time.
  ::testing::Test::RecordProperty("longest_step_ns", static_cast<int>(longest_step_ns));
  std::printf("longest joint manager step: %lld ns (the save blocked for %d periods)\n",
              static_cast<long long>(longest_step_ns), kBlockedPeriods);
}

}  // namespace
}  // namespace rescue::app
