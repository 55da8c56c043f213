// Test doubles for the joint manager's ports: single-threaded bounded queues, a published joint-sample
// table, an event recorder and a storage whose writes can be made to fail.
#pragma once

#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <thread>
#include <string>
#include <vector>

#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/error_joints_worker.hpp"
#include "core/app/tasks/joint_events.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "drivers/joint/joint_units.hpp"

namespace rescue::app::testing {

template <typename T>
class FakeQueue final : public MessageSink<T>, public MessageSource<T> {
 public:
  explicit FakeQueue(std::size_t capacity = 16) : capacity_(capacity) {}
  bool try_send(const T& message) noexcept override {
    if (items_.size() >= capacity_) return false;
    items_.push_back(message);
    return true;
  }
  bool try_receive(T& out) noexcept override {
    if (items_.empty()) return false;
    out = items_.front();
    items_.pop_front();
    return true;
  }
  std::size_t size() const { return items_.size(); }
  void set_capacity(std::size_t c) { capacity_ = c; }

 private:
  std::size_t capacity_;
  std::deque<T> items_;
};

// The shared-memory table the handler publishes: tests write it directly.
class FakeSamples final : public JointSampleSource {
 public:
  FakeSamples() {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      JointSample& s = robot[j];
      s.reachable = true;
      const JointLimits& lim = kJoints[j].limits;
      // Distinct per joint, and a whole encoder count (what a drive reports).
      s.position_rad = drivers::counts_to_rad(drivers::rad_to_counts(0.5 * (lim.position_min_rad + lim.position_max_rad)) +
                                              static_cast<std::int32_t>(j));
      s.position_ref_rad = s.position_rad;
    }
  }
  bool read(RobotSample& out) noexcept override {
    out = robot;
    return true;
  }
  // The handler's behaviour on a loss: reachable off, last values left in place.
  void lose(JointMask mask) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if (mask & joint_bit(j)) robot[j].reachable = false;
    }
  }
  RobotSample robot{};
};

class EventLog final : public JointEventSink {
 public:
  void on_event(const JointEvent& e) noexcept override {
    events.push_back(e);
    char line[512];
    format_event(e, line, sizeof line);
    lines.emplace_back(line);
    if (echo) std::printf("  [%lld ms] %s\n", static_cast<long long>(e.time / hal::kNsPerMs), line);
  }
  std::vector<JointEvent> of(JointEventKind kind) const {
    std::vector<JointEvent> out;
    for (const auto& e : events) {
      if (e.kind == kind) out.push_back(e);
    }
    return out;
  }
  bool contains(const std::string& text) const {
    for (const auto& l : lines) {
      if (l.find(text) != std::string::npos) return true;
    }
    return false;
  }
  std::vector<JointEvent> events;
  std::vector<std::string> lines;
  bool echo{false};
};

// Wraps another storage; `fail_saves` makes save() fail like a full or read-only disk.
class FlakyStorage final : public ErrorJointsStorage {
 public:
  explicit FlakyStorage(ErrorJointsStorage& inner) : inner_(inner) {}
  ErrorJointsLoad load() noexcept override { return inner_.load(); }
  Status save(const ErrorJointsContents& c) noexcept override {
    ++saves;
    if (fail_saves) return make_error(Errc::io_error, "write temporary file", 28 /* ENOSPC */);
    return inner_.save(c);
  }
  Result<std::uint32_t> set_aside() noexcept override { return inner_.set_aside(); }
  bool fail_saves{false};
  int saves{0};

 private:
  ErrorJointsStorage& inner_;
};

// The storage worker (core/app/tasks/error_joints_worker.hpp) run inline, for tests on one thread: a
// request is saved as it is sent (or, while `paused`, when finish() is called: a disk that takes its
// time), and its outcome waits in the results queue for the joint manager's next read. The firmware
// runs the same ErrorJointsStorageWorker on its own thread.
class InlineStorageWorker final : public MessageSink<ErrorJointsSaveRequest>, public MessageSource<ErrorJointsSaveResult> {
 public:
  explicit InlineStorageWorker(ErrorJointsStorage& storage) : worker_(requests_, results_, storage) {}
  bool try_send(const ErrorJointsSaveRequest& request) noexcept override {
    if (!requests_.try_send(request)) return false;
    ++requests;
    if (!paused) (void)worker_.serve_one();
    return true;
  }
  bool try_receive(ErrorJointsSaveResult& out) noexcept override { return results_.try_receive(out); }
  // Saves every request waiting (the paused disk is done).
  void finish() {
    while (worker_.serve_one()) {
    }
  }
  std::size_t waiting() const { return requests_.size(); }
  bool paused{false};
  int requests{0};

 private:
  FakeQueue<ErrorJointsSaveRequest> requests_{2};
  FakeQueue<ErrorJointsSaveResult> results_{2};
  ErrorJointsStorageWorker worker_;
};

// save() blocks until released (a disk that takes its time), then saves for real.
class BlockingDisk final : public ErrorJointsStorage {
 public:
  explicit BlockingDisk(ErrorJointsStorage& inner) : inner_(inner) {}
  ErrorJointsLoad load() noexcept override { return inner_.load(); }
  Status save(const ErrorJointsContents& c) noexcept override {
    std::unique_lock<std::mutex> lock(mutex_);
    in_save.store(true);
    released_.wait(lock, [this] { return release_; });
    const Status saved = inner_.save(c);
    saves_returned.fetch_add(1);
    in_save.store(false);
    return saved;
  }
  Result<std::uint32_t> set_aside() noexcept override { return inner_.set_aside(); }
  void release() {
    std::lock_guard<std::mutex> lock(mutex_);
    release_ = true;
    released_.notify_all();
  }
  std::atomic<bool> in_save{false};
  std::atomic<int> saves_returned{0};

 private:
  ErrorJointsStorage& inner_;
  std::mutex mutex_;
  std::condition_variable released_;
  bool release_{false};
};

// The storage worker as `run` wires it: over SpscQueues, on a thread of its own (until stop()).
class ThreadedStorageWorker {
 public:
  explicit ThreadedStorageWorker(ErrorJointsStorage& storage)
      : worker_(worker_requests_, worker_results_, storage), thread_([this] {
          while (!stop_.load()) {
            if (!worker_.serve_one()) std::this_thread::yield();
          }
        }) {}
  ~ThreadedStorageWorker() { stop(); }
  ThreadedStorageWorker(const ThreadedStorageWorker&) = delete;
  ThreadedStorageWorker& operator=(const ThreadedStorageWorker&) = delete;
  // The joint manager's ends of the two queues.
  void wire(JointManagerPorts& ports) {
    ports.save_requests = &requests_;
    ports.save_results = &results_;
  }
  void stop() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
  }

 private:
  SpscQueue<ErrorJointsSaveRequest, 2> request_queue_;
  SpscQueue<ErrorJointsSaveResult, 2> result_queue_;
  SpscMessageSink<ErrorJointsSaveRequest, 2> requests_{request_queue_};
  SpscMessageSource<ErrorJointsSaveRequest, 2> worker_requests_{request_queue_};
  SpscMessageSink<ErrorJointsSaveResult, 2> worker_results_{result_queue_};
  SpscMessageSource<ErrorJointsSaveResult, 2> results_{result_queue_};
  ErrorJointsStorageWorker worker_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// A fresh temporary state directory, removed at the end.
class TempStateDir {
 public:
  TempStateDir() {
    std::string templ = ::testing::TempDir() + "state-XXXXXX";
    path = mkdtemp(templ.data()) != nullptr ? templ : std::string();
  }
  ~TempStateDir() { (void)std::system(("rm -rf '" + path + "'").c_str()); }
  std::string file() const { return path + "/" + ErrorJointsFileStorage::kFileName; }
  std::string path;
};

// Everything a JointManager needs, wired to fakes.
struct Rig {
  explicit Rig(ErrorJointsStorage& storage_in) : storage(storage_in), worker(storage_in) {}
  JointManagerPorts ports() {
    JointManagerPorts p{&reports, &notices, &commands, &samples, &storage, &wall, &log, nullptr};
    p.save_requests = &worker;
    p.save_results = &worker;
    return p;
  }
  void command(JointMask joints, fsm::JointInput input, ControlMode mode = ControlMode::none) {
    ASSERT_TRUE(commands.try_send(JointCommand{joints, input, mode, JointCommandKind::dfa_input}));
  }
  FakeQueue<LostJointsReport> reports;
  FakeQueue<JointManagerNotice> notices;
  FakeQueue<JointCommand> commands{64};
  FakeSamples samples;
  ErrorJointsStorage& storage;
  InlineStorageWorker worker;
  hal::ManualWallClock wall{1'700'000'000'000'000'000LL};
  EventLog log;
};

// A joint manager wired to a Rig and a real error-joints file in a fresh state directory, stepped a
// millisecond at a time: the fixture of the joint manager's command tests.
class JointManagerFixture : public ::testing::Test {
 protected:
  JointManagerFixture() : storage(dir.path.c_str()), rig(storage), manager(rig.ports()) {}

  void step() {
    now += hal::kNsPerMs;
    manager.step(now);
  }
  // The first two commands of "initialize robot": CSP selected, the reference where each joint stands.
  void select_csp_at_current_position() {
    rig.command(kAllJoints, fsm::JointInput::select_mode, ControlMode::cyclic_position);
    rig.command(kAllJoints, fsm::JointInput::set_reference);
  }

  TempStateDir dir;
  ErrorJointsFileStorage storage;
  Rig rig;
  JointManager manager;
  hal::Nanoseconds now{0};
};

}  // namespace rescue::app::testing
