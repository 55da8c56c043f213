// The joint manager's event sink in the firmware: on_event (on the joint manager's real-time thread)
// only copies the event into a bounded single-producer single-consumer queue; the logger thread pops
// and prints them (JointEventPrinter). Nothing blocks: when the queue is full the event is dropped
// and counted (dropped()), and the logger says how many. No heap, no system call, no stdio on the
// real-time side (toolchain/rt_verify.py proves it: JointEventQueue::on_event is the only event
// sink in `run`).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>

#include "core/app/tasks/joint_events.hpp"
#include "core/concurrency/spsc_queue.hpp"

namespace rescue::app {

class JointEventQueue final : public JointEventSink {
 public:
  static constexpr std::size_t kDepth = 256;  // events between two logger passes (5 ms)

  // Producer: the joint manager's thread (and before it starts, the start-up thread).
  void on_event(const JointEvent& event) noexcept override {
    if (!queue_.try_push(event)) dropped_.fetch_add(1, std::memory_order_relaxed);
  }
  // Consumer: the logger thread.
  bool pop(JointEvent& event) noexcept { return queue_.try_pop(event); }
  std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

 private:
  SpscQueue<JointEvent, kDepth> queue_;
  std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace rescue::app
