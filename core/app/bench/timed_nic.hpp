// The NIC under the master in the benchmarks, with the time spent inside send/receive counted in
// TSC ticks: the wire's or the simulator's time, not the master's (bench master, bench sim, bench fig4).
#pragma once

#include <cstdint>

#include "hal/net/nic.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::app {

class TimedNic final : public hal::Nic {
 public:
  TimedNic(hal::Nic& inner, const hal::TscTimer& timer) noexcept : inner_(&inner), timer_(timer) {}
  void set_inner(hal::Nic& inner) noexcept { inner_ = &inner; }
  Status send(ConstByteSpan frame) noexcept override {
    const std::uint64_t t0 = timer_.start();
    const Status s = inner_->send(frame);
    send_ticks_ += timer_.stop() - t0;
    return s;
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    const std::uint64_t t0 = timer_.start();
    Result<std::size_t> r = inner_->receive(buffer, deadline);
    receive_ticks_ += timer_.stop() - t0;
    return r;
  }
  hal::Clock& clock() noexcept override { return inner_->clock(); }
  const char* name() const noexcept override { return inner_->name(); }
  hal::NicStats stats() const noexcept override { return inner_->stats(); }
  std::uint64_t ticks() const noexcept { return send_ticks_ + receive_ticks_; }
  // Apart: with the in-process simulated robot, send() is the simulator processing the frame
  // (SimulatedNic::send runs the segment) and receive() the wait for the frame's modelled return
  // (and its copy), so a handler period splits into the handler's own work, the simulator's share
  // and the wait for the frame (bench fig4).
  std::uint64_t send_ticks() const noexcept { return send_ticks_; }
  std::uint64_t receive_ticks() const noexcept { return receive_ticks_; }

 private:
  hal::Nic* inner_;
  const hal::TscTimer& timer_;
  std::uint64_t send_ticks_{0};
  std::uint64_t receive_ticks_{0};
};

}  // namespace rescue::app
