// The NIC under the master in the benchmarks, with the time spent inside send/receive counted in
// TSC ticks: the wire's or the simulator's time, not the master's (bench master, bench sim).
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
    ticks_ += timer_.stop() - t0;
    return s;
  }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    const std::uint64_t t0 = timer_.start();
    Result<std::size_t> r = inner_->receive(buffer, deadline);
    ticks_ += timer_.stop() - t0;
    return r;
  }
  hal::Clock& clock() noexcept override { return inner_->clock(); }
  const char* name() const noexcept override { return inner_->name(); }
  hal::NicStats stats() const noexcept override { return inner_->stats(); }
  std::uint64_t ticks() const noexcept { return ticks_; }

 private:
  hal::Nic* inner_;
  const hal::TscTimer& timer_;
  std::uint64_t ticks_{0};
};

}  // namespace rescue::app
