// The handler is never blocked by the error-joints file write: the joint manager runs on its own
// thread, its storage worker on another, and the write is held open (a disk that takes forever) while
// the handler's thread runs thousands of further cycles with the lost joints pending and every other
// joint commanded. Only when the write is released does the answer arrive. If the handler waited for the write, this test would
// hang (and CTest's timeout would fail it). No sleeps and no timing: progress is observed via atomics.
// The threads share what the firmware's tasks share: lock-free SPSC queues and the seqlocked samples.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "core/app/tasks/lost_joint_tracker.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "tests/support/joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

const JointMask kElbowCut = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));

class NullLog final : public JointEventSink {
 public:
  void on_event(const JointEvent&) noexcept override {}
};

TEST(HandlerDuringFileWrite, KeepsCyclingAndIsAnsweredWhenTheWriteCompletes) {
  testing::TempStateDir dir;
  ErrorJointsFileStorage files(dir.path.c_str());
  testing::BlockingDisk disk(files);
  testing::ThreadedStorageWorker storage(disk);
  SpscQueue<LostJointsReport, 16> report_queue;
  SpscQueue<JointManagerNotice, 16> notice_queue;
  SpscQueue<JointCommand, 16> command_queue;
  Seqlock<RobotSample> published;
  SpscMessageSink<LostJointsReport, 16> report_sink(report_queue);
  SpscMessageSource<LostJointsReport, 16> report_source(report_queue);
  SpscMessageSink<JointManagerNotice, 16> notice_sink(notice_queue);
  SpscMessageSource<JointManagerNotice, 16> notice_source(notice_queue);
  SpscMessageSource<JointCommand, 16> commands(command_queue);
  SeqlockSampleSource samples(published);
  hal::ManualWallClock wall(1'700'000'000'000'000'000LL);
  NullLog log;
  JointManagerPorts ports{&report_source, &notice_sink, &commands, &samples, &disk, &wall, &log, nullptr};
  storage.wire(ports);
  JointManager manager(ports);

  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> handler_cycles{0};
  std::atomic<JointMask> handler_pending{0};
  std::atomic<JointMask> handler_confirmed{0};
  std::atomic<std::uint64_t> commanded_healthy_cycles{0};

  std::thread handler([&] {
    LostJointTracker tracker(report_sink, notice_source, 0);
    testing::FakeSamples robot;  // the handler's view of the joints, published every cycle
    for (std::uint64_t cycle = 1; !stop.load(); ++cycle) {
      const JointMask cut = cycle > 100 ? kElbowCut : 0;
      robot.lose(cut);
      published.write(robot.robot);
      tracker.on_cycle(cycle, static_cast<hal::Nanoseconds>(cycle) * hal::kNsPerMs, cut);
      if (((kAllJoints & ~kElbowCut) & tracker.excluded()) == 0) commanded_healthy_cycles.fetch_add(1);
      handler_pending.store(tracker.pending());
      handler_confirmed.store(tracker.confirmed());
      handler_cycles.store(cycle);
    }
  });
  std::thread joint_manager([&] {
    for (hal::Nanoseconds now = 0; !stop.load(); now += hal::kNsPerMs) manager.step(now);
  });

  while (!disk.in_save.load()) std::this_thread::yield();  // the joint manager is inside the write
  const std::uint64_t at_write = handler_cycles.load();
  while (handler_cycles.load() < at_write + 5000) std::this_thread::yield();  // ...and the handler runs on
  EXPECT_TRUE(disk.in_save.load());
  EXPECT_EQ(handler_pending.load(), kElbowCut);  // answer not yet given: lost joints held, not commanded
  EXPECT_EQ(handler_confirmed.load(), 0u);

  disk.release();
  while (handler_confirmed.load() != kElbowCut) std::this_thread::yield();
  stop.store(true);
  handler.join();
  joint_manager.join();
  storage.stop();

  EXPECT_EQ(commanded_healthy_cycles.load(), handler_cycles.load());  // every cycle of the healthy joints
  EXPECT_EQ(files.load().decoded.contents.joints(), kElbowCut);
}

}  // namespace
}  // namespace rescue::app
