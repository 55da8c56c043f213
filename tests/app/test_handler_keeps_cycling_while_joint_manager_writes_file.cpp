// The handler is never blocked by the error-joints file write: the joint manager runs on its own
// thread and its write is held open (a disk that takes forever) while the handler's thread runs
// thousands of further cycles with the lost joints pending and every other joint commanded. Only when
// the write is released does the answer arrive. If the handler waited for the write, this test would
// hang (and CTest's timeout would fail it). No sleeps and no timing: progress is observed via atomics.
#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "core/app/lost_joint_tracker.hpp"
#include "joint_manager_fakes.hpp"

namespace rescue::app {
namespace {

const JointMask kElbowCut = joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"));

// A queue two threads may share (the firmware uses the lock-free SPSC queues of shared memory).
template <typename T>
class LockedQueue final : public MessageSink<T>, public MessageSource<T> {
 public:
  bool try_send(const T& m) noexcept override {
    std::lock_guard<std::mutex> lock(mutex_);
    return inner_.try_send(m);
  }
  bool try_receive(T& out) noexcept override {
    std::lock_guard<std::mutex> lock(mutex_);
    return inner_.try_receive(out);
  }

 private:
  std::mutex mutex_;
  testing::FakeQueue<T> inner_;
};

// The handler's published samples, shared between the threads.
class LockedSamples final : public JointSampleSource {
 public:
  bool read(RobotSample& out) noexcept override {
    std::lock_guard<std::mutex> lock(mutex_);
    out = inner_.robot;
    return true;
  }
  void lose(JointMask mask) {
    std::lock_guard<std::mutex> lock(mutex_);
    inner_.lose(mask);
  }

 private:
  std::mutex mutex_;
  testing::FakeSamples inner_;
};

// save() blocks until released.
class StuckDisk final : public ErrorJointsStorage {
 public:
  explicit StuckDisk(ErrorJointsStorage& inner) : inner_(inner) {}
  ErrorJointsLoad load() noexcept override { return inner_.load(); }
  Status save(const ErrorJointsContents& c) noexcept override {
    std::unique_lock<std::mutex> lock(mutex_);
    in_save.store(true);
    released_.wait(lock, [this] { return release_; });
    return inner_.save(c);
  }
  Status set_aside() noexcept override { return inner_.set_aside(); }
  void release() {
    std::lock_guard<std::mutex> lock(mutex_);
    release_ = true;
    released_.notify_all();
  }
  std::atomic<bool> in_save{false};

 private:
  ErrorJointsStorage& inner_;
  std::mutex mutex_;
  std::condition_variable released_;
  bool release_{false};
};

class NullLog final : public JointEventSink {
 public:
  void on_event(const JointEvent&) noexcept override {}
};

TEST(HandlerDuringFileWrite, KeepsCyclingAndIsAnsweredWhenTheWriteCompletes) {
  testing::TempStateDir dir;
  ErrorJointsFileStorage files(dir.path.c_str());
  StuckDisk disk(files);
  LockedQueue<LostJointsReport> reports;
  LockedQueue<JointManagerNotice> notices;
  LockedQueue<JointCommand> commands;
  LockedSamples samples;
  hal::ManualWallClock wall(1'700'000'000'000'000'000LL);
  NullLog log;
  JointManager manager(JointManagerPorts{&reports, &notices, &commands, &samples, &disk, &wall, &log});

  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> handler_cycles{0};
  std::atomic<JointMask> handler_pending{0};
  std::atomic<JointMask> handler_confirmed{0};
  std::atomic<std::uint64_t> commanded_healthy_cycles{0};

  std::thread handler([&] {
    LostJointTracker tracker(reports, notices, 0);
    for (std::uint64_t cycle = 1; !stop.load(); ++cycle) {
      const JointMask cut = cycle > 100 ? kElbowCut : 0;
      samples.lose(cut);
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

  EXPECT_EQ(commanded_healthy_cycles.load(), handler_cycles.load());  // every cycle of the healthy joints
  EXPECT_EQ(files.load().decoded.contents.joints(), kElbowCut);
}

}  // namespace
}  // namespace rescue::app
